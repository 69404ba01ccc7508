"""Sanity of the contact-mechanics forward model."""

import numpy as np

from anytip.sensor.fleet import FleetConfig
from anytip.sensor.geometry import angles_from_point, contact_rotation
from anytip.sensor.physics import coupling, elastic_pressure, hysteresis_factor, relax
from anytip.sensor.variation import draw_unit

UNIT = draw_unit(FleetConfig(severity=0.0), np.random.default_rng(0))


def _pressure(theta, phi, force_contact):
    theta, phi = np.atleast_1d(theta), np.atleast_1d(phi)
    rot = contact_rotation(theta, phi)
    points = UNIT.radius_m * rot[:, :, 2]
    force_base = np.einsum("nij,nj->ni", rot, np.atleast_2d(force_contact))
    return elastic_pressure(points, force_base, UNIT) * coupling(points, UNIT)


def test_press_over_top_barometer_raises_it_most():
    baro = 3
    theta, phi = angles_from_point(UNIT.array("baro_positions_m")[baro][None])
    p = _pressure(theta, phi, [0.0, 0.0, -10.0])[0]
    assert p.argmax() == baro
    assert 2e4 < p[baro] < 3e5


def test_pressure_grows_with_force():
    theta, phi = angles_from_point(UNIT.array("baro_positions_m")[0][None])
    forces = np.array([[0.0, 0.0, -f] for f in (1.0, 5.0, 10.0, 25.0)])
    p = _pressure(np.repeat(theta, 4), np.repeat(phi, 4), forces)
    assert np.all(np.diff(p[:, 0]) > 0)
    assert 5e4 < p[-1, 0] < 3e5


def test_no_force_no_pressure():
    assert np.all(_pressure(0.1, -0.5, [0.0, 0.0, 0.0]) == 0.0)


def test_shear_raises_pressure_ahead_and_lowers_it_behind():
    # Contact on top between the x = 0 and x = 5 mm barometers; contact x is base +x here.
    theta, phi = 0.0, np.deg2rad(15.0)
    base = _pressure(theta, phi, [0.0, 0.0, -10.0])[0]
    sheared = _pressure(theta, phi, [6.0, 0.0, -10.0])[0]
    ahead, behind = [2, 3], [0, 1]
    assert np.all(sheared[ahead] > base[ahead])
    assert np.all(sheared[behind] < base[behind])


def test_hysteresis_only_on_unloading():
    fn = np.array([0.0, 5.0, 10.0, 5.0, 0.0, 4.0, 8.0, 4.0])
    press = np.array([0, 0, 0, 0, 0, 1, 1, 1])
    k = hysteresis_factor(fn, press, 0.1)
    np.testing.assert_allclose(k[[1, 2, 5, 6]], 1.0)
    assert k[3] == 1.1 and k[7] == 1.1


def test_relaxation_decays_to_fraction():
    step = np.ones((2000, 1))
    y = relax(step, 0.005, 0.1, 0.5)
    assert y[0, 0] > 0.99 and abs(y[-1, 0] - 0.9) < 1e-3
