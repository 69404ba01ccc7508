"""The leave-one-out margin on the fleet factor (`anytip.uncertainty.fleet_margin`)."""

import numpy as np
import pytest

from anytip.uncertainty.conformal import fleet_factor
from anytip.uncertainty.fleet_margin import (
    Learner,
    factor_ceiling,
    leave_one_out_margin,
    left_out_widths,
    pooled_factor,
)


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
    assert leave_one_out_margin(alike).shortfall() is None and got.shortfall() is None
    assert leave_one_out_margin(alike[:2]).shortfall() is None


def test_each_left_out_learner_gets_the_factor_of_the_others():
    """A learner's width left out is its own half-width times the factor of the rest alone: changing
    its own test rows moves every other learner's width and never its own."""
    units = [gaussian_learner(1.0 + 0.1 * k, (1 + 0.05 * k) / 1.6449) for k in range(4)]
    base, floor, low, high = left_out_widths(units)
    rest = units[1:]
    factor = fleet_factor(np.stack([u.own for u in rest]), np.stack([u.needed for u in rest]))
    assert base[0] == pytest.approx(units[0].own * factor)
    assert (floor[:, 0] < low[:, 0]).all() and (low[:, 0] < high[:, 0]).all()
    moved = left_out_widths([gaussian_learner(1.0, 2.0 / 1.6449), *rest])[0]
    assert moved[0] == pytest.approx(base[0]) and (moved[1:] > base[1:]).all()


def test_a_margin_the_rule_cannot_find_says_why():
    """Margin 1 because no grid value met the rule: a unit whose test rows need 2x what its plan
    says stays below the floor up to 1.2; one that needs 1.5x reaches it only at a margin that
    pushes most of the alike units above the band."""
    alike = [gaussian_learner(1.0, 1 / 1.6449 * (1 + 0.01 * k)) for k in range(-3, 4)]
    lost = leave_one_out_margin([*alike * 3, gaussian_learner(1.0, 2.0 / 1.6449)])
    assert lost.margin == 1.0 and min(lost.below.values()) == 1
    assert lost.shortfall() == "1 left-out unit-output(s) stayed below the floor at every margin up to 1.2"
    wide = leave_one_out_margin([*alike * 3, gaussian_learner(1.0, 1.5 / 1.6449)])
    assert wide.margin == 1.0 and wide.below[1.18] == 0 and wide.in_band[1.18] < 0.9
    assert wide.shortfall() == ("none falls below the floor only from a margin of 1.18, where 41% lie in the "
                                "band (the rule asks 90%)")


def test_factor_ceiling_finds_the_best_factor_with_and_without_the_floor():
    """Three units of one output whose band, as a factor on their own half-width of 2, is [1, 2],
    [1.5, 2.5] and [3, 4], each floor 0.9 of its lower edge: a factor in [1.5, 2] puts two of three
    in the band; leaving none below the floor needs 2.7, and then 3 puts only the last one in."""
    own = np.full((3, 1), 2.0)
    low = own * np.array([[1.0], [1.5], [3.0]])
    high = own * np.array([[2.0], [2.5], [4.0]])
    got = factor_ceiling(own, 0.9 * low, low, high)
    assert got.free[0] == 1.5 and got.free_in_band == 2 / 3
    assert got.safe[0] == 3.0 and got.safe_in_band == 1 / 3
    # a second output whose units agree: both factors put all three in, and the shares are means
    two = factor_ceiling(np.hstack([own, own]), np.hstack([0.9 * low, own * 0.8]), np.hstack([low, own]),
                         np.hstack([high, own * 1.2]))
    assert list(two.free) == [1.5, 1.0]
    assert two.free_in_band == (2 + 3) / 6 and two.safe_in_band == (1 + 3) / 6


def test_a_recorded_learner_is_read_by_name_and_pooled_into_the_factor_and_margin():
    """`Learner.from_record` reads {field: {output: half-width}} in the names' order and refuses a
    missing or non-positive value by field and output; `pooled_factor` is the geometric mean of
    needed over own per output, with the margin the learners choose."""
    rec = {f: {"b": 2.0 * k, "a": 1.0 * k} for k, f in enumerate(Learner._fields, start=1)}
    got = Learner.from_record(rec, ("a", "b"))
    assert got.own.tolist() == [1.0, 2.0] and got.needed.tolist() == [2.0, 4.0]
    for bad in (None, -1.0, float("nan"), True, "1"):
        with pytest.raises(ValueError, match="at_low.b: .* is not a finite positive half-width"):
            Learner.from_record({**rec, "at_low": {"a": 3.0, "b": bad}}, ("a", "b"))
    with pytest.raises(ValueError, match="own.c"):
        Learner.from_record(rec, ("a", "c"))
    units = [Learner(np.array([1.0]), np.array([n]), np.array([0.1]), np.array([0.1]), np.array([10.0]))
             for n in (1.0, 4.0)]
    factor, choice = pooled_factor(units)
    assert factor.tolist() == pytest.approx([2.0]) and choice.margin == 1.0  # two learners: no margin
