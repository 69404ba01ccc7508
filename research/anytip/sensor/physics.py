"""Contact mechanics of the elastomer dome: contact load -> pressure at each barometer (Pa).

The hydrostatic pressure p = -(s_xx + s_yy + s_zz) / 3 under a point force F on an
elastic half-space is, summing Boussinesq (normal load) and Cerruti (tangential load)
(Johnson, Contact Mechanics, 1985, ch. 3; Timoshenko and Goodier, Theory of Elasticity):

    p(rho) = (1 + nu) / (3 pi) * (F . rho) / |rho|^3

with rho running from the load point to the field point and F the force on the body.
The load is smoothed over the Hertz contact patch by |rho|^2 -> |rho|^2 + a^2 with
a = (3 Fn R / (4 E*))^(1/3). The dome is not a half-space: the formula is applied in
the tangent frame at the contact, which is exact only for field points much closer to
the contact than the 10 mm radius; docs/simulator.md states the approximation.
Shapes: N rows, C barometers.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter

from anytip.sensor.variation import UnitParams


def hertz_radius(normal_force_n: np.ndarray, unit: UnitParams) -> np.ndarray:
    """(N,) m contact radius a = (3 Fn R / (4 E*))^(1/3), E* = E / (1 - nu^2), rigid indenter."""
    e_star = unit.modulus_pa / (1.0 - unit.poisson**2)
    fn = np.clip(normal_force_n, 0.0, None)
    return np.cbrt(3.0 * fn * unit.indenter_radius_m / (4.0 * e_star))


def elastic_pressure(points: np.ndarray, force_base: np.ndarray, unit: UnitParams) -> np.ndarray:
    """(N, C) Pa elastomer pressure at each barometer, before the barometer's own coupling.

    points (N, 3) m true load points on the surface; force_base (N, 3) N force on the
    sensor in the base frame (a press points inward).
    """
    pos = unit.array("baro_positions_m")
    normals = points / np.linalg.norm(points, axis=1, keepdims=True)
    a = hertz_radius(-np.einsum("ni,ni->n", force_base, normals), unit)
    rho = pos[None, :, :] - points[:, None, :]
    f_dot_rho = np.einsum("ncj,nj->nc", rho, force_base)
    dist2 = np.einsum("ncj,ncj->nc", rho, rho) + (a * a)[:, None]
    return (1.0 + unit.poisson) / (3.0 * np.pi) * f_dot_rho / (dist2 * np.sqrt(dist2))


def coupling(points: np.ndarray, unit: UnitParams) -> np.ndarray:
    """(N, C) dimensionless coupling of each barometer to a load at points (N, 3) m.

    Port direction: (1 + kappa u.n_b + d_b.u) / (1 + kappa), u the unit vector from
    barometer b towards the load, n_b its port normal, d_b a casting anisotropy vector.
    Voids: a bubble of strength s, radius w0 at q_b shadows loads whose path to the
    barometer passes near it: factor 1 - s exp(-dist^2 / (2 w^2)), w = w0 + 1 mm.
    """
    pos, normals = unit.array("baro_positions_m"), unit.array("baro_normals")
    to_load = points[:, None, :] - pos[None, :, :]
    length = np.linalg.norm(to_load, axis=2, keepdims=True)
    u = to_load / np.maximum(length, 1e-12)
    kappa = unit.direction_coupling
    facing = np.einsum("ncj,cj->nc", u, normals)
    defect = np.einsum("ncj,cj->nc", u, unit.array("direction_defect"))
    direction = (1.0 + kappa * facing + defect) / (1.0 + kappa)
    return np.clip(direction, 0.0, None) * _void_shadow(to_load, length[..., 0], unit)


def _void_shadow(to_load: np.ndarray, length: np.ndarray, unit: UnitParams) -> np.ndarray:
    """(N, C) factor in (0, 1]: loss of coupling from a void near the load path."""
    strength = unit.array("bubble_strength")
    if not strength.any():
        return np.ones(to_load.shape[:2])
    rel = unit.array("bubble_center_m") - unit.array("baro_positions_m")  # (C, 3)
    t = np.clip(np.einsum("ncj,cj->nc", to_load, rel) / np.maximum(length**2, 1e-18), 0.0, 1.0)
    closest = t[..., None] * to_load
    dist2 = np.sum((closest - rel[None]) ** 2, axis=2)
    width = unit.array("bubble_radius_m") + 1e-3
    return 1.0 - strength * np.exp(-dist2 / (2.0 * width**2))


def hysteresis_factor(
    normal_force_n: np.ndarray, press_id: np.ndarray, amount: float
) -> np.ndarray:
    """(N,) rate-independent loading/unloading factor 1 + 4 h u (1 - u).

    u = Fn / (running max of Fn within the press): 1 while loading, falling on
    unloading, so a release reads up to (1 + h) times the loading reading at the same
    force. press_id (N,) non-decreasing integers, one per press (rest rows join the
    preceding press).
    """
    fn = np.clip(normal_force_n, 0.0, None)
    offset = press_id.astype(float) * (fn.max(initial=0.0) + 1.0)
    running_max = np.maximum.accumulate(fn + offset) - offset
    u = fn / np.maximum(running_max, 1e-9)
    return 1.0 + 4.0 * amount * u * (1.0 - u)


def relax(pressure: np.ndarray, dt_s: float, fraction: float, tau_s: float) -> np.ndarray:
    """(N, C) viscoelastic relaxation, a standard linear solid: y = p - beta * LP_tau(p).

    Under a step load the reading decays from p to (1 - beta) p with time constant
    tau; on release it undershoots by beta p and recovers. LP is a first-order IIR.
    """
    if fraction == 0.0:
        return pressure
    alpha = np.exp(-dt_s / tau_s)
    lowpassed = lfilter([1.0 - alpha], [1.0, -alpha], pressure, axis=0)
    return pressure - fraction * lowpassed


def shifted_points(
    points: np.ndarray, rotation: np.ndarray, force_contact: np.ndarray, compliance_m_per_n: float
) -> np.ndarray:
    """(N, 3) m true load points: the contact slides along the shear by compliance * shear.

    rotation (N, 3, 3) base <- contact; force_contact (N, 3) N. The slid point is
    projected back onto the sphere through the original radius.
    """
    slide = np.zeros_like(force_contact)
    slide[:, :2] = compliance_m_per_n * force_contact[:, :2]
    moved = points + np.einsum("nij,nj->ni", rotation, slide)
    radius = np.linalg.norm(points, axis=1, keepdims=True)
    return moved * (radius / np.linalg.norm(moved, axis=1, keepdims=True))
