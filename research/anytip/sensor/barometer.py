"""Barometer read-out: temperature, gain, offset, saturation, noise and quantisation.

Turns the pressure the elastomer applies to each barometer (Pa, relative) into the
absolute reading the firmware logs (Pa, about 1e5 at rest, not tared). Shapes: N rows,
C barometers.
"""

from __future__ import annotations

import numpy as np

from anytip.sensor.fleet import RunConditions
from anytip.sensor.variation import UnitParams

REFERENCE_C = 25.0  # temperature at which gain and offset are nominal


def temperature_trace(
    time_s: np.ndarray, cond: RunConditions, rng: np.random.Generator
) -> np.ndarray:
    """(N,) degC slow temperature of the dome over one run.

    Ambient plus a warm-up rise (1 - exp(-t / tau)) plus two slow sinusoids of random
    period (2-10 min) and phase.
    """
    ambient = cond.ambient_c + cond.ambient_sigma_c * rng.standard_normal()
    rise = cond.warmup_c * rng.uniform(0.5, 1.5)
    periods = rng.uniform(120.0, 600.0, 2)
    phases = rng.uniform(0.0, 2.0 * np.pi, 2)
    wander = np.sin(2.0 * np.pi * time_s[:, None] / periods + phases).sum(axis=1) / 2.0
    return ambient + rise * (1.0 - np.exp(-time_s / cond.warmup_tau_s)) + cond.wander_c * wander


def channel_temperature(
    trace_c: np.ndarray, unit: UnitParams, cond: RunConditions, rng: np.random.Generator
) -> np.ndarray:
    """(N, C) degC each barometer's own temperature reading: offset, noise, quantisation."""
    temp = trace_c[:, None] + unit.array("temp_sensor_offset_c")[None, :]
    temp = temp + cond.temp_noise_c * rng.standard_normal(temp.shape)
    return quantise(temp, cond.temp_quant_c)


def quantise(x: np.ndarray, step: float) -> np.ndarray:
    """Round to multiples of `step` (no-op for step 0)."""
    return x if step <= 0 else np.round(x / step) * step


def soft_limit(x: np.ndarray, low: np.ndarray, high: np.ndarray, knee: float) -> np.ndarray:
    """Identity in the middle, tanh knees near both limits, clip at [low, high].

    The knee starts `knee` of the way from `center` = (low + high) / 2 to each limit.
    """
    center, half = (low + high) / 2.0, (high - low) / 2.0
    start = knee * half
    dev = x - center
    width = np.maximum(half - start, 1e-9)
    over = np.abs(dev) - start
    bent = np.where(over > 0, np.sign(dev) * (start + width * np.tanh(over / width)), dev)
    return np.clip(center + bent, low, high)


def read_out(
    pressure_pa: np.ndarray,
    temp_c: np.ndarray,
    atmosphere_pa: float,
    unit: UnitParams,
    rng: np.random.Generator,
) -> np.ndarray:
    """(N, C) absolute readings in Pa from elastomer pressure (N, C) Pa and temperature (N, C) degC.

    reading = atm + preload + tc_off dT + gain (1 + tc_gain dT) p, then the soft
    full-scale limit, white noise, quantisation and the hard limits.
    """
    d_temp = temp_c - REFERENCE_C
    gain = unit.array("channel_gain") * (1.0 + unit.array("tc_gain_per_c") * d_temp)
    rest = atmosphere_pa + unit.array("preload_pa") + unit.array("tc_offset_pa_per_c") * d_temp
    low = np.full(unit.n_channels, unit.floor_pa)
    high = unit.array("full_scale_pa")
    reading = soft_limit(rest + gain * pressure_pa, low, high, _knee(unit, atmosphere_pa))
    reading = reading + unit.array("noise_pa") * rng.standard_normal(reading.shape)
    return np.clip(quantise(reading, unit.quant_pa), low, high)


def _knee(unit: UnitParams, atmosphere_pa: float) -> np.ndarray:
    """Knee as a fraction of the half range such that the upper knee sits at
    atm + knee_fraction * (full_scale - atm), per channel."""
    high, low = unit.array("full_scale_pa"), unit.floor_pa
    center, half = (high + low) / 2.0, (high - low) / 2.0
    upper_knee = atmosphere_pa + unit.knee_fraction * (high - atmosphere_pa)
    return np.clip((upper_knee - center) / half, 0.0, 1.0)
