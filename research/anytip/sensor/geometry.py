"""Sensor geometry and contact kinematics of the 8-barometer fingertip (SaLoutos et al. 2023).

Frames: the base frame sits at the centre of the dome sphere. A contact at angles
(theta, phi) has the pose `T_base,contact = Rot_y(phi) Rot_x(theta) Trans(0, 0, r)`;
the contact-frame z-axis is the outward surface normal, so a press (force on the
sensor pointing inward) has Fz < 0. All lengths are metres, all angles radians.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

SENSOR_MODEL = "fingertip-8baro-r10"
RADIUS_M = 0.010


def _nominal_positions() -> np.ndarray:
    """(8, 3) m: four barometers on the top board (facing +z), four on the side board (facing -x).

    The two boards meet near the corner of the dome that lies between them; the
    layout is mirror-symmetric about the plane x = -z (phi = -45 deg), the centre of
    the sensing region.
    """
    top = [(x, y, 0.0025) for x in (0.0, 0.005) for y in (-0.003, 0.003)]
    side = [(-0.0025, y, z) for z in (0.0, -0.005) for y in (-0.003, 0.003)]
    return np.array(top + side, dtype=float)


def _nominal_normals() -> np.ndarray:
    """(8, 3) unit vectors each barometer's port faces: +z for the top board, -x for the side."""
    return np.array([(0.0, 0.0, 1.0)] * 4 + [(-1.0, 0.0, 0.0)] * 4, dtype=float)


@dataclass(frozen=True)
class SensorGeometry:
    """Shape of one sensor model: dome radius (m), barometer positions (C, 3) m and
    port normals (C, 3), and the sensing region in degrees (theta, phi ranges)."""

    radius_m: float = RADIUS_M
    baro_positions_m: np.ndarray = field(default_factory=_nominal_positions)
    baro_normals: np.ndarray = field(default_factory=_nominal_normals)
    theta_range_deg: tuple[float, float] = (-45.0, 45.0)
    phi_range_deg: tuple[float, float] = (-135.0, 45.0)
    sensor_model: str = SENSOR_MODEL

    @property
    def n_channels(self) -> int:
        return int(self.baro_positions_m.shape[0])


NOMINAL = SensorGeometry()


def _rot_x(a: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotations about x by angles a (N,) rad."""
    c, s = np.cos(a), np.sin(a)
    o, z = np.ones_like(a), np.zeros_like(a)
    return np.stack(
        [np.stack([o, z, z], -1), np.stack([z, c, -s], -1), np.stack([z, s, c], -1)], -2
    )


def _rot_y(a: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotations about y by angles a (N,) rad."""
    c, s = np.cos(a), np.sin(a)
    o, z = np.ones_like(a), np.zeros_like(a)
    return np.stack(
        [np.stack([c, z, s], -1), np.stack([z, o, z], -1), np.stack([-s, z, c], -1)], -2
    )


def contact_rotation(theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotation base <- contact, Rot_y(phi) Rot_x(theta); columns are the
    contact-frame x, y (shear) and z (outward normal) axes in the base frame."""
    theta, phi = np.broadcast_arrays(np.asarray(theta, float), np.asarray(phi, float))
    return _rot_y(phi.ravel()) @ _rot_x(theta.ravel())


def contact_frame(theta: np.ndarray, phi: np.ndarray, r: float = RADIUS_M) -> np.ndarray:
    """(N, 4, 4) homogeneous transforms T_base,contact = Rot_y(phi) Rot_x(theta) Trans(0, 0, r)."""
    rot = contact_rotation(theta, phi)
    out = np.zeros((rot.shape[0], 4, 4))
    out[:, :3, :3] = rot
    out[:, :3, 3] = rot[:, :, 2] * r
    out[:, 3, 3] = 1.0
    return out


def contact_normal(theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """(N, 3) outward unit normal at the contact: (cos th sin ph, -sin th, cos th cos ph)."""
    theta, phi = np.broadcast_arrays(np.asarray(theta, float), np.asarray(phi, float))
    ct = np.cos(theta.ravel())
    return np.stack(
        [ct * np.sin(phi.ravel()), -np.sin(theta.ravel()), ct * np.cos(phi.ravel())], -1
    )


def contact_point(theta: np.ndarray, phi: np.ndarray, r: float = RADIUS_M) -> np.ndarray:
    """(N, 3) m contact point on the dome of radius r."""
    return r * contact_normal(theta, phi)


def angles_from_point(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverse kinematics: (N, 3) points (any radius > 0) -> theta (N,), phi (N,) in rad.

    theta in [-pi/2, pi/2], phi in (-pi, pi]; exact inverse of `contact_point` there.
    """
    p = np.atleast_2d(np.asarray(points, float))
    theta = np.arctan2(-p[:, 1], np.hypot(p[:, 0], p[:, 2]))
    phi = np.arctan2(p[:, 0], p[:, 2])
    return theta, phi


def force_to_base(force_contact: np.ndarray, theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """(N, 3) N: force given in the contact frame (Fx, Fy shear, Fz normal) -> base frame."""
    rot = contact_rotation(theta, phi)
    return np.einsum("nij,nj->ni", rot, np.atleast_2d(force_contact))


def force_to_contact(force_base: np.ndarray, theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """(N, 3) N: force given in the base frame -> contact frame."""
    rot = contact_rotation(theta, phi)
    return np.einsum("nji,nj->ni", rot, np.atleast_2d(force_base))


def contact_frame_inverse(theta: np.ndarray, phi: np.ndarray, r: float = RADIUS_M) -> np.ndarray:
    """(N, 4, 4) T_contact,base = T_base,contact^-1 = Trans(0, 0, -r) Rot_x(-theta) Rot_y(-phi).

    Maps base-frame homogeneous points (m) into the contact frame: the contact point goes to
    the origin, the dome centre to (0, 0, -r). theta, phi rad, broadcast to (N,).
    """
    rot_t = contact_rotation(theta, phi).transpose(0, 2, 1)
    out = np.zeros((rot_t.shape[0], 4, 4))
    out[:, :3, :3] = rot_t
    out[:, 2, 3] = -r  # -R^T (R e_z r) = -r e_z
    out[:, 3, 3] = 1.0
    return out
