"""Contact kinematics of the fingertip against hand-computed cases."""

import numpy as np
import pytest

from anytip.sensor.geometry import (
    NOMINAL,
    RADIUS_M,
    angles_from_point,
    contact_frame,
    contact_normal,
    contact_point,
    force_to_base,
    force_to_contact,
)


def test_top_of_dome():
    np.testing.assert_allclose(contact_point(0.0, 0.0), [[0.0, 0.0, RADIUS_M]], atol=1e-15)


def test_phi_90_is_plus_x():
    np.testing.assert_allclose(contact_point(0.0, np.pi / 2), [[RADIUS_M, 0.0, 0.0]], atol=1e-15)


def test_theta_45_tilts_towards_minus_y():
    s = RADIUS_M / np.sqrt(2)
    np.testing.assert_allclose(contact_point(np.pi / 4, 0.0), [[0.0, -s, s]], atol=1e-15)


def test_frame_matches_point_and_normal():
    rng = np.random.default_rng(0)
    theta, phi = rng.uniform(-0.8, 0.8, 50), rng.uniform(-2.3, 0.8, 50)
    frames = contact_frame(theta, phi)
    assert frames.shape == (50, 4, 4)
    np.testing.assert_allclose(frames[:, :3, 3], contact_point(theta, phi), atol=1e-15)
    np.testing.assert_allclose(frames[:, :3, 2], contact_normal(theta, phi), atol=1e-15)
    rot = frames[:, :3, :3]
    np.testing.assert_allclose(
        rot @ rot.transpose(0, 2, 1), np.broadcast_to(np.eye(3), rot.shape), atol=1e-12
    )


def test_round_trip_angles_point_angles():
    rng = np.random.default_rng(1)
    theta = rng.uniform(-np.pi / 4, np.pi / 4, 1000)
    phi = rng.uniform(-3 * np.pi / 4, np.pi / 4, 1000)
    back_theta, back_phi = angles_from_point(contact_point(theta, phi))
    np.testing.assert_allclose(back_theta, theta, atol=1e-12)
    np.testing.assert_allclose(back_phi, phi, atol=1e-12)


def test_press_points_inward_and_force_round_trip():
    theta, phi = np.array([0.3, -0.2]), np.array([-1.0, 0.5])
    press = np.array([[0.0, 0.0, -5.0], [1.0, -2.0, -5.0]])
    base = force_to_base(press, theta, phi)
    assert np.all(np.einsum("ni,ni->n", base, contact_normal(theta, phi)) == pytest.approx(-5.0))
    np.testing.assert_allclose(force_to_contact(base, theta, phi), press, atol=1e-12)


def test_barometers_inside_dome():
    assert NOMINAL.n_channels == 8
    assert np.all(np.linalg.norm(NOMINAL.baro_positions_m, axis=1) < RADIUS_M - 2e-3)
