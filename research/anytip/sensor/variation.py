"""Unit-to-unit variation: `UnitParams` holds every per-unit number, `draw_unit` samples one.

Every random number is drawn whatever the severity, so one seed gives the same
standard-normal draws at every severity: severity 0 is the nominal unit, and a
larger severity moves each unit further along the same direction.
"""

from __future__ import annotations

import numpy as np
from pydantic import BaseModel, ConfigDict

from anytip.sensor.fleet import FleetConfig
from anytip.sensor.geometry import NOMINAL, RADIUS_M, SENSOR_MODEL

Vec = list[float]


class UnitParams(BaseModel):
    """One manufactured unit. Lists of length C are per barometer; (C, 3) lists are
    per-barometer vectors in the base frame. SI units unless the name says otherwise.
    Serialises to JSON with `model_dump_json()` and back with `model_validate_json()`."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    sensor_model: str = SENSOR_MODEL
    radius_m: float = RADIUS_M
    baro_positions_m: list[Vec]
    baro_normals: list[Vec]
    modulus_pa: float
    poisson: float
    indenter_radius_m: float
    channel_gain: Vec
    direction_coupling: float
    direction_defect: list[Vec]
    bubble_center_m: list[Vec]
    bubble_radius_m: Vec
    bubble_strength: Vec
    relax_fraction: float
    relax_tau_s: float
    hysteresis: float
    shift_compliance_m_per_n: float
    preload_pa: Vec
    full_scale_pa: Vec
    floor_pa: float
    knee_fraction: float
    noise_pa: Vec
    quant_pa: float
    tc_offset_pa_per_c: Vec
    tc_gain_per_c: Vec
    temp_sensor_offset_c: Vec

    @property
    def n_channels(self) -> int:
        return len(self.channel_gain)

    def array(self, name: str) -> np.ndarray:
        """A field as a float64 numpy array."""
        return np.asarray(getattr(self, name), dtype=float)


def _lognormal(rng: np.random.Generator, nominal: float, sigma: float, size: int | None = None):
    """nominal * exp(sigma * z); with sigma = 0 exactly nominal."""
    return nominal * np.exp(sigma * rng.standard_normal(size))


def _normal(rng: np.random.Generator, mean: float, sigma: float, size) -> np.ndarray:
    """mean + sigma * z; adding the mean last turns -0.0 into 0.0, so identical units
    serialise to identical JSON."""
    return sigma * rng.standard_normal(size) + mean


def _tilt(normals: np.ndarray, sigma_rad: float, rng: np.random.Generator) -> np.ndarray:
    """Perturb unit vectors (C, 3) by small random rotations of std sigma_rad; renormalise."""
    noisy = normals + sigma_rad * rng.standard_normal(normals.shape)
    return noisy / np.linalg.norm(noisy, axis=1, keepdims=True)


def _positions(rng: np.random.Generator, sev: float, config: FleetConfig) -> np.ndarray:
    """(C, 3) m barometer positions: nominal + per-board shift + per-barometer jitter."""
    pos = NOMINAL.baro_positions_m.copy()
    board = np.repeat(rng.standard_normal((2, 3)), 4, axis=0)
    jitter = rng.standard_normal(pos.shape)
    sp = config.spread
    return pos + sev * (sp.board_shift_sigma_m * board + sp.position_sigma_m * jitter)


def _bubbles(
    rng: np.random.Generator, sev: float, config: FleetConfig, pos: np.ndarray, normals: np.ndarray
):
    """Casting voids: at most one per barometer, 0.5-2.5 mm in front of its port."""
    c = pos.shape[0]
    present = rng.random(c) < min(1.0, sev * config.spread.bubble_probability)
    direction = _tilt(normals, 0.6, rng)
    center = pos + direction * rng.uniform(0.5e-3, 2.5e-3, (c, 1))
    radius = rng.uniform(0.3e-3, 1.0e-3, c)
    strength = rng.uniform(0.2, 1.0, c) * config.spread.bubble_strength_max
    # A unit without a void stores zeros, so identical units compare equal.
    center = np.where(present[:, None], center, 0.0)
    return center, np.where(present, radius, 0.0), np.where(present, strength, 0.0)


def draw_unit(config: FleetConfig, rng: np.random.Generator) -> UnitParams:
    """Sample one unit of the fleet. At severity 0 every number is the nominal value."""
    nom, sp, sev = config.nominal, config.spread, config.severity
    c = NOMINAL.n_channels
    pos = _positions(rng, sev, config)
    normals = _tilt(NOMINAL.baro_normals, np.deg2rad(sev * sp.normal_tilt_sigma_deg), rng)
    bubble_center, bubble_radius, bubble_strength = _bubbles(rng, sev, config, pos, normals)
    return UnitParams(
        sensor_model=config.sensor_model,
        baro_positions_m=pos.tolist(),
        baro_normals=normals.tolist(),
        modulus_pa=float(_lognormal(rng, nom.modulus_pa, sev * sp.modulus_log_sigma)),
        poisson=nom.poisson,
        indenter_radius_m=nom.indenter_radius_m,
        channel_gain=_lognormal(
            rng, nom.coupling_gain, sev * sp.channel_gain_log_sigma, c
        ).tolist(),
        direction_coupling=nom.direction_coupling,
        direction_defect=_normal(rng, 0.0, sev * sp.direction_defect_sigma, (c, 3)).tolist(),
        bubble_center_m=bubble_center.tolist(),
        bubble_radius_m=bubble_radius.tolist(),
        bubble_strength=bubble_strength.tolist(),
        relax_fraction=float(
            min(0.9, _lognormal(rng, nom.relax_fraction, sev * sp.relax_log_sigma))
        ),
        relax_tau_s=float(_lognormal(rng, nom.relax_tau_s, sev * sp.relax_log_sigma)),
        hysteresis=float(min(0.9, _lognormal(rng, nom.hysteresis, sev * sp.hysteresis_log_sigma))),
        shift_compliance_m_per_n=float(
            _lognormal(rng, nom.shift_compliance_m_per_n, sev * sp.shift_log_sigma)
        ),
        preload_pa=_normal(rng, nom.preload_pa, sev * sp.preload_sigma_pa, c).tolist(),
        full_scale_pa=_lognormal(rng, nom.full_scale_pa, sev * sp.full_scale_log_sigma, c).tolist(),
        floor_pa=nom.floor_pa,
        knee_fraction=nom.knee_fraction,
        noise_pa=_lognormal(rng, nom.noise_pa, sev * sp.noise_log_sigma, c).tolist(),
        quant_pa=nom.quant_pa,
        tc_offset_pa_per_c=_normal(
            rng, nom.tc_offset_pa_per_c, sev * sp.tc_offset_sigma_pa_per_c, c
        ).tolist(),
        tc_gain_per_c=_normal(rng, nom.tc_gain_per_c, sev * sp.tc_gain_sigma_per_c, c).tolist(),
        temp_sensor_offset_c=_normal(rng, 0.0, sev * sp.temp_sensor_sigma_c, c).tolist(),
    )
