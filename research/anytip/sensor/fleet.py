"""Fleet configuration: nominal physics, unit-to-unit spreads, rig conditions, severity.

`FleetConfig()` with no arguments is the default fleet (configs/fleets/default.yaml
holds the same values). `severity` multiplies every unit-to-unit spread: 0 gives
identical units with exactly the nominal parameters; per-run noise processes
(`RunConditions`) are rig properties and are not scaled. Distributions are described
in docs/simulator.md.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field

from anytip.errors import AnytipError
from anytip.sensor.geometry import SENSOR_MODEL
from anytip.validation import load_yaml, validate_strict

_STRICT = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class NominalParams(BaseModel):
    """Parameters of the ideal unit. SI units unless the name says otherwise."""

    model_config = _STRICT

    modulus_pa: float = Field(1.5e6, gt=0, description="Young's modulus of the polyurethane")
    poisson: float = Field(0.49, gt=0, lt=0.5, description="Poisson ratio (nearly incompressible)")
    indenter_radius_m: float = Field(0.010, gt=0, description="effective Hertz radius of contact")
    coupling_gain: float = Field(
        1.5, gt=0, description="barometer reading per Pa of elastomer pressure"
    )
    direction_coupling: float = Field(0.3, ge=0, lt=1, description="port-facing sensitivity kappa")
    relax_fraction: float = Field(0.08, ge=0, lt=1, description="fraction of pressure that relaxes")
    relax_tau_s: float = Field(0.8, gt=0, description="relaxation time constant")
    hysteresis: float = Field(0.06, ge=0, lt=1, description="peak unloading excess, fraction")
    shift_compliance_m_per_n: float = Field(
        5e-5, ge=0, description="load-point slide per N of shear"
    )
    preload_pa: float = Field(3000.0, description="casting preload on each barometer")
    full_scale_pa: float = Field(2.1e5, gt=0, description="absolute upper limit of a barometer")
    floor_pa: float = Field(1.0e4, ge=0, description="absolute lower limit of a barometer")
    knee_fraction: float = Field(
        0.85, gt=0, le=1, description="soft-knee start, fraction of headroom"
    )
    noise_pa: float = Field(8.0, ge=0, description="barometer white noise, std")
    quant_pa: float = Field(1.0, ge=0, description="barometer quantisation step (0 = none)")
    tc_offset_pa_per_c: float = Field(150.0, description="offset temperature coefficient")
    tc_gain_per_c: float = Field(
        0.002, description="gain temperature coefficient, fraction per degC"
    )


class SpreadParams(BaseModel):
    """Unit-to-unit spreads at severity 1. `*_log_sigma` are lognormal sigmas of a factor
    on the nominal value; `*_sigma_*` are Gaussian standard deviations in the named unit."""

    model_config = _STRICT

    channel_gain_log_sigma: float = Field(0.35, ge=0)
    modulus_log_sigma: float = Field(0.2, ge=0)
    position_sigma_m: float = Field(
        5e-4, ge=0, description="per-barometer position jitter, per axis"
    )
    board_shift_sigma_m: float = Field(
        2e-4, ge=0, description="common shift of each board, per axis"
    )
    normal_tilt_sigma_deg: float = Field(4.0, ge=0)
    direction_defect_sigma: float = Field(0.12, ge=0, description="per-barometer anisotropy vector")
    bubble_probability: float = Field(
        0.15, ge=0, le=1, description="chance of a void per barometer"
    )
    bubble_strength_max: float = Field(0.6, ge=0, lt=1, description="max fraction of coupling lost")
    relax_log_sigma: float = Field(0.3, ge=0)
    hysteresis_log_sigma: float = Field(0.3, ge=0)
    shift_log_sigma: float = Field(0.3, ge=0)
    preload_sigma_pa: float = Field(2000.0, ge=0)
    full_scale_log_sigma: float = Field(0.08, ge=0)
    noise_log_sigma: float = Field(0.3, ge=0)
    tc_offset_sigma_pa_per_c: float = Field(100.0, ge=0)
    tc_gain_sigma_per_c: float = Field(0.001, ge=0)
    temp_sensor_sigma_c: float = Field(0.3, ge=0)


class RunConditions(BaseModel):
    """Per-run rig and environment: drawn afresh for every run, not scaled by severity."""

    model_config = _STRICT

    atmosphere_pa: float = Field(101325.0, gt=0)
    atmosphere_sigma_pa: float = Field(800.0, ge=0)
    ambient_c: float = 23.0
    ambient_sigma_c: float = Field(1.5, ge=0)
    warmup_c: float = Field(2.0, ge=0, description="mean temperature rise over a run")
    warmup_tau_s: float = Field(240.0, gt=0)
    wander_c: float = Field(0.2, ge=0, description="amplitude of slow temperature wander")
    temp_noise_c: float = Field(0.02, ge=0)
    temp_quant_c: float = Field(0.01, ge=0)
    force_noise_n: float = Field(0.08, ge=0, description="F/T label white noise, std per axis")
    force_bias_n: float = Field(0.1, ge=0, description="F/T label bias per run, std per axis")
    angle_noise_rad: float = Field(0.01, ge=0, description="rig positioning error per press, std")


class FleetConfig(BaseModel):
    """A fleet: nominal unit, spreads, run conditions and the severity knob (>= 0)."""

    model_config = _STRICT

    sensor_model: str = SENSOR_MODEL
    severity: float = Field(1.0, ge=0)
    nominal: NominalParams = NominalParams()
    spread: SpreadParams = SpreadParams()
    run: RunConditions = RunConditions()


def fleet_config_from_dict(data: Any, path: str = "<dict>") -> FleetConfig:
    """Validate a mapping into a FleetConfig; raise AnytipError naming `path` and the key."""
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise AnytipError(
            f"{path}: a fleet config must be a mapping of keys, got {type(data).__name__}"
        )
    return validate_strict(FleetConfig, data, path)


def load_fleet_config(path: str | Path) -> FleetConfig:
    """Read a fleet YAML (keys as in FleetConfig; omitted keys keep their defaults)."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise AnytipError(f"{path}: cannot read fleet config ({e})") from None
    data = load_yaml(text, str(path))
    return fleet_config_from_dict(data, str(path))
