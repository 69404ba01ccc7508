"""The leave-one-out margin on the fleet factor (`anytip.uncertainty.fleet_margin`)."""

import numpy as np

from anytip.uncertainty.fleet_margin import Learner, leave_one_out_margin


def gaussian_learner(own: float, sigma: float) -> Learner:
    """A one-output unit whose test residuals are N(0, sigma^2): the half-widths at which |r|
    covers 0.90 (needed), 0.80, 0.85 and 0.95 of them."""
    z = (1.6449, 1.2816, 1.4395, 1.9600)
    return Learner(np.array([own]), *(np.array([q * sigma]) for q in z))


def test_alike_units_need_no_margin_and_one_hard_unit_asks_for_one():
    alike = [gaussian_learner(1.0, 1 / 1.6449 * (1 + 0.01 * k)) for k in range(-3, 4)]
    got = leave_one_out_margin(alike)
    assert got.margin == 1.0 and got.below[1.0] == 0 and got.in_band[1.0] == 1.0
    # a unit whose test rows need 1.3x what its plan says: left out, the others' factor leaves it
    # below the floor until the margin lifts it, while the alike units stay in the band
    hard = [*alike * 3, gaussian_learner(1.0, 1.3 / 1.6449)]
    got = leave_one_out_margin(hard)
    assert got.below[1.0] == 1 and got.margin > 1.0 and got.below[got.margin] == 0
    assert got.in_band[got.margin] >= 0.9
    assert leave_one_out_margin(alike[:2]).margin == 1.0  # too few to leave one out
