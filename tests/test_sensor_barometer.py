"""The barometer read-out a simulated unit's firmware logs: linear in the elastomer pressure away
from its limits, gain and offset moving with temperature, a soft knee to full scale, noise and
quantisation on top, never outside the hard limits."""

from __future__ import annotations

import numpy as np
import pytest

from anytip.sensor.barometer import REFERENCE_C, quantise, read_out, soft_limit
from anytip.sensor.fleet import FleetConfig
from anytip.sensor.simulate import unit_rng
from anytip.sensor.variation import draw_unit

ATM = 101_325.0


@pytest.fixture
def unit():
    return draw_unit(FleetConfig(), unit_rng(3, 0))


def quiet(unit):
    """The same unit without noise or quantisation: the read-out's deterministic part."""
    return unit.model_copy(update={"noise_pa": tuple(0.0 for _ in range(unit.n_channels)), "quant_pa": 0.0})


def test_small_pressures_read_linearly_with_the_units_gain_at_reference_temperature(unit):
    u = quiet(unit)
    p = np.linspace(0, 2000, 11)[:, None] * np.ones((1, u.n_channels))
    temp = np.full_like(p, REFERENCE_C)
    r = read_out(p, temp, ATM, u, np.random.default_rng(0))
    rest = ATM + u.array("preload_pa")
    np.testing.assert_allclose(r, rest + u.array("channel_gain") * p, rtol=0, atol=1e-6)


def test_temperature_moves_offset_and_gain(unit):
    u = quiet(unit)
    p = np.full((1, u.n_channels), 1000.0)
    cold, warm = (read_out(p, np.full_like(p, t), ATM, u, np.random.default_rng(0)) for t in (20.0, 30.0))
    d_temp = 10.0
    expected = (u.array("tc_offset_pa_per_c") * d_temp
                + u.array("channel_gain") * u.array("tc_gain_per_c") * d_temp * 1000.0)
    np.testing.assert_allclose(warm - cold, expected[None], rtol=1e-9, atol=1e-6)


def test_readings_stay_within_the_hard_limits_and_saturate_smoothly(unit):
    p = np.linspace(-2e5, 2e6, 4001)[:, None] * np.ones((1, unit.n_channels))
    r = read_out(p, np.full_like(p, REFERENCE_C), ATM, unit, np.random.default_rng(1))
    assert (r >= unit.floor_pa).all() and (r <= unit.array("full_scale_pa")).all()
    r_quiet = read_out(p, np.full_like(p, REFERENCE_C), ATM, quiet(unit), np.random.default_rng(1))
    assert (np.diff(r_quiet, axis=0) >= 0).all()  # monotone: more pressure never reads less
    np.testing.assert_allclose(r_quiet[-1], unit.array("full_scale_pa"), rtol=1e-6)


def test_noise_and_quantisation(unit):
    p = np.zeros((20_000, unit.n_channels))
    r = read_out(p, np.full_like(p, REFERENCE_C), ATM, unit, np.random.default_rng(2))
    if unit.quant_pa > 0:
        np.testing.assert_allclose(r / unit.quant_pa, np.round(r / unit.quant_pa), atol=1e-6)
    sd = r.std(0)
    expected = np.sqrt(unit.array("noise_pa") ** 2 + unit.quant_pa ** 2 / 12)
    np.testing.assert_allclose(sd, expected, rtol=0.1)


def test_soft_limit_and_quantise():
    x = np.array([-10.0, 0.0, 5.0, 9.0, 10.0, 50.0])
    y = soft_limit(x, np.array(-10.0), np.array(10.0), 0.5)
    assert y[1] == 0 and y[2] == 5.0  # identity inside the knee
    assert 5.0 < y[3] < 9.0  # bent towards the limit past the knee
    assert 10.0 - 1e-6 < y[-1] <= 10.0 and -10.0 < y[0] < -5.0  # approaches, never passes, the limits
    assert quantise(np.array([0.26, -0.26]), 0.5).tolist() == [0.5, -0.5]
    assert quantise(np.array([0.26]), 0.0).tolist() == [0.26]
