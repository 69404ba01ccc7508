"""Contact kinematics: T_base,contact(theta, phi), its inverse, the normal and force transforms,
against cases computed by hand."""

import numpy as np
import pytest

from anytip.sensor.geometry import (
    RADIUS_M,
    contact_frame,
    contact_frame_inverse,
    contact_normal,
    contact_point,
    force_to_base,
    force_to_contact,
)

R = RADIUS_M
S2 = np.sqrt(0.5)


def homogeneous(p):
    return np.append(np.asarray(p, float), 1.0)


def test_top_of_dome_is_a_pure_translation():
    expected = np.eye(4)
    expected[2, 3] = R
    np.testing.assert_allclose(contact_frame(0.0, 0.0)[0], expected, atol=1e-15)
    inverse = np.eye(4)
    inverse[2, 3] = -R
    np.testing.assert_allclose(contact_frame_inverse(0.0, 0.0)[0], inverse, atol=1e-15)
    np.testing.assert_allclose(contact_point(0.0, 0.0)[0], [0.0, 0.0, R], atol=1e-15)
    np.testing.assert_allclose(contact_normal(0.0, 0.0)[0], [0.0, 0.0, 1.0], atol=1e-15)


def test_phi_90_deg_turns_the_frame_about_y():
    # Rot_y(90 deg) = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]: contact x -> base -z, contact z -> base +x
    expected = np.array([[0, 0, 1, R], [0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1]], float)
    np.testing.assert_allclose(contact_frame(0.0, np.pi / 2)[0], expected, atol=1e-15)
    np.testing.assert_allclose(contact_normal(0.0, np.pi / 2)[0], [1.0, 0.0, 0.0], atol=1e-15)
    # a 5 N press along the contact's -z is -5 N along base x; 1 N of contact-x shear is base -z
    np.testing.assert_allclose(force_to_base([[1.0, 0.0, -5.0]], 0.0, np.pi / 2)[0], [-5.0, 0.0, -1.0],
                               atol=1e-14)


def test_theta_90_deg_turns_the_frame_about_x():
    # Rot_x(90 deg) = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]: contact z -> base -y, contact y -> base +z
    expected = np.array([[1, 0, 0, 0], [0, 0, -1, -R], [0, 1, 0, 0], [0, 0, 0, 1]], float)
    np.testing.assert_allclose(contact_frame(np.pi / 2, 0.0)[0], expected, atol=1e-15)
    np.testing.assert_allclose(force_to_base([[0.0, 2.0, 0.0]], np.pi / 2, 0.0)[0], [0.0, 0.0, 2.0],
                               atol=1e-15)


def test_theta_30_phi_minus_45_normal_and_point():
    th, ph = np.deg2rad(30.0), np.deg2rad(-45.0)
    normal = [np.cos(th) * -S2, -0.5, np.cos(th) * S2]  # (cos th sin ph, -sin th, cos th cos ph)
    np.testing.assert_allclose(contact_normal(th, ph)[0], normal, atol=1e-15)
    np.testing.assert_allclose(contact_frame(th, ph)[0, :3, 3], R * np.array(normal), atol=1e-15)
    # a pure press of 4 N on the sensor points against the outward normal
    np.testing.assert_allclose(force_to_base([[0.0, 0.0, -4.0]], th, ph)[0], -4.0 * np.array(normal),
                               atol=1e-14)


def test_inverse_undoes_the_transform_and_maps_the_contact_to_the_origin():
    rng = np.random.default_rng(3)
    theta, phi = rng.uniform(-0.8, 0.8, 40), rng.uniform(-2.3, 0.8, 40)
    T, T_inv = contact_frame(theta, phi), contact_frame_inverse(theta, phi)
    np.testing.assert_allclose(T @ T_inv, np.broadcast_to(np.eye(4), T.shape), atol=1e-14)
    np.testing.assert_allclose(T_inv, np.linalg.inv(T), atol=1e-12)
    points = np.array([homogeneous(p) for p in contact_point(theta, phi)])
    np.testing.assert_allclose(np.einsum("nij,nj->ni", T_inv, points)[:, :3], 0.0, atol=1e-15)
    centre = np.einsum("nij,j->ni", T_inv, homogeneous([0.0, 0.0, 0.0]))[:, :3]
    np.testing.assert_allclose(centre, np.tile([0.0, 0.0, -R], (40, 1)), atol=1e-15)


def test_force_transforms_match_the_frame_rotation():
    theta, phi = np.array([0.2, -0.5, 0.7]), np.array([-1.2, 0.3, -2.0])
    f_contact = np.array([[1.0, 0.0, -3.0], [0.0, -2.0, -1.0], [0.5, 0.5, -10.0]])
    rot = contact_frame(theta, phi)[:, :3, :3]
    base = force_to_base(f_contact, theta, phi)
    np.testing.assert_allclose(base, np.einsum("nij,nj->ni", rot, f_contact), atol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(base, axis=1), np.linalg.norm(f_contact, axis=1))
    np.testing.assert_allclose(force_to_contact(base, theta, phi), f_contact, atol=1e-14)
    # the normal component is the contact-frame Fz
    np.testing.assert_allclose(np.einsum("ni,ni->n", base, contact_normal(theta, phi)), f_contact[:, 2])


@pytest.mark.parametrize("r", [0.005, 0.02])
def test_radius_scales_translation_only(r):
    T = contact_frame(0.3, -0.4, r)[0]
    assert np.linalg.norm(T[:3, 3]) == pytest.approx(r)
    np.testing.assert_allclose(contact_frame_inverse(0.3, -0.4, r)[0, :3, 3], [0.0, 0.0, -r], atol=1e-15)


def test_scalar_and_array_angles_broadcast():
    assert contact_frame_inverse(0.1, np.zeros(5)).shape == (5, 4, 4)
    assert contact_frame(np.zeros((2, 3)), 0.2).shape == (6, 4, 4)
