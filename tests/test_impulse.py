"""Collision impulse ratio: the closed form against numerical integration, limits, scaling, errors."""

import itertools

import numpy as np
import pytest

from anytip.analysis import impulse as imp
from anytip.errors import AnytipError

NOM = imp.NOMINAL


def params(**changes):
    return {**NOM, **changes}


GRID = [params(t_l=t, k=k, v0=v, f_in=f, m_f=m)
        for t, k, v, f, m in itertools.product([0.0, 0.003, 0.007, 0.015, 0.03], [300.0, 1500.0, 6000.0],
                                               [0.05, 0.15, 0.8], [0.0, 2.0, 10.0, 60.0], [0.0, 0.005])]


def test_closed_form_matches_numerical_integration_on_a_grid():
    diffs = [abs(imp.collision_impulse_ratio(**p) - imp.numeric_impulse_ratio(**p)) for p in GRID]
    assert max(diffs) < 1e-8


def test_closed_form_displacement_and_duration_match_the_solver():
    for p in (NOM, params(t_l=0.0, f_in=3.0), params(t_l=0.02, k=800.0), params(f_in=100.0, v0=1.0)):
        sim = imp.simulate_collision(**p)
        np.testing.assert_allclose(imp.displacement(sim.t, **p), sim.x, rtol=0, atol=1e-12)
        assert float(imp.collision(**p).duration) == pytest.approx(sim.duration, abs=1e-10)
        assert sim.x[-1] == pytest.approx(0.0, abs=1e-12)


def test_nominal_by_hand_from_the_integral_of_k_x():
    """The same impulse from integrating k x(t) over both phases, not from momentum."""
    m_f, m_r, t_l, k, v0, f_in = (NOM[n] for n in imp.PARAMS)
    w = np.sqrt(k / m_r)
    x1, v1, xs = v0 / w * np.sin(w * t_l), v0 * np.cos(w * t_l), f_in / k
    r, psi = np.hypot(x1 + xs, v1 / w), np.arctan2(v1 / w, x1 + xs)
    tau = (psi + np.arccos(xs / r)) / w
    phase1 = m_r * v0 * (1 - np.cos(w * t_l))
    phase2 = -f_in * tau + k * r / w * (np.sin(w * tau - psi) + np.sin(psi))
    eta = (m_f * v0 + phase1 + phase2) / ((m_f + 2 * m_r) * v0)
    assert imp.collision_impulse_ratio(**NOM) == pytest.approx(eta, rel=1e-12)
    assert 0.36 < eta < 0.37


def test_without_actuator_the_bounce_is_elastic():
    c = imp.collision(**params(f_in=0.0))
    w = np.sqrt(NOM["k"] / NOM["m_r"])
    assert float(c.eta) == pytest.approx(1.0, abs=1e-14)
    assert float(c.duration) == pytest.approx(np.pi / w)
    assert float(c.end_velocity) == pytest.approx(-NOM["v0"])
    assert float(c.impulse) == pytest.approx((NOM["m_f"] + 2 * NOM["m_r"]) * NOM["v0"])


def test_latency_beyond_the_half_period_leaves_eta_at_one():
    half = np.pi * np.sqrt(NOM["m_r"] / NOM["k"])
    assert imp.collision_impulse_ratio(**params(t_l=half * 1.01)) == pytest.approx(1.0, abs=1e-12)
    assert imp.collision_impulse_ratio(**params(t_l=half * 0.99)) < 1.0


def test_eta_grows_with_latency_and_shrinks_with_actuator_force():
    etas = imp.collision(**params(t_l=np.linspace(0, 0.025, 50))).eta
    assert np.all(np.diff(etas) > 0)
    forces = imp.collision(**params(f_in=np.linspace(0, 100, 50))).eta
    assert np.all(np.diff(forces) < 0)


def test_eta_depends_on_v0_and_f_in_only_through_their_ratio():
    base = imp.collision_impulse_ratio(**NOM)
    for s in (0.2, 3.0, 10.0):
        scaled = imp.collision_impulse_ratio(**params(v0=NOM["v0"] * s, f_in=NOM["f_in"] * s))
        assert scaled == pytest.approx(base, rel=1e-12)
    # with f_in fixed, eta is not invariant to v0: a faster approach meets a relatively weaker actuator
    etas = [imp.collision_impulse_ratio(**params(v0=v)) for v in (0.05, 0.15, 0.5, 1.0)]
    assert np.all(np.diff(etas) > 0) and etas[-1] - etas[0] > 0.3


def test_simplified_forms_bound_and_miss_the_closed_form():
    p = [NOM[n] for n in ("m_f", "m_r", "t_l", "k", "v0")]
    instant = float(imp.instant_stop_impulse_ratio(*p))
    exact = imp.collision_impulse_ratio(**NOM)
    assert instant < exact  # the instant stop drops the impulse after t_l
    gaps = [imp.collision_impulse_ratio(**params(f_in=f)) - instant for f in (1e3, 1e5, 1e7)]
    assert 0 < gaps[2] < gaps[1] < gaps[0] and gaps[2] < 2e-4  # the f_in -> infinity limit
    assert float(imp.sinusoid_impulse_ratio(**NOM)) < 0  # the free-sinusoid form goes negative
    assert float(imp.sinusoid_impulse_ratio(**params(f_in=0.0))) == pytest.approx(1.0)


def test_eta_grid_shape_and_values():
    t_l, k = np.linspace(0, 0.02, 5), np.array([500.0, 1500.0, 3000.0])
    grid = imp.eta_grid("t_l", t_l, "k", k)
    assert grid.shape == (3, 5)
    assert grid[1, 0] == pytest.approx(imp.collision_impulse_ratio(**params(t_l=0.0, k=1500.0)))
    with pytest.raises(AnytipError, match="unknown collision parameter 'mass'"):
        imp.eta_grid("mass", t_l, "k", k)


@pytest.mark.parametrize("name, value, message", [
    ("m_f", -0.001, r"m_f must be finite and >= 0, got -0.001"),
    ("m_r", 0.0, r"m_r must be finite and > 0, got 0.0"),
    ("k", -5.0, r"k must be finite and > 0, got -5.0"),
    ("v0", 0.0, r"v0 must be finite and > 0"),
    ("t_l", -0.001, r"t_l must be finite and >= 0"),
    ("f_in", -1.0, r"f_in must be finite and >= 0, got -1.0"),
    ("k", float("nan"), r"k must be finite"),
])
def test_bad_parameters_name_the_parameter_and_value(name, value, message):
    with pytest.raises(AnytipError, match=message):
        imp.collision_impulse_ratio(**params(**{name: value}))
    with pytest.raises(AnytipError, match=message):
        imp.simulate_collision(**params(**{name: value}))
