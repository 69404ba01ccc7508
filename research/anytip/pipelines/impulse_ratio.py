"""The paper's analyses of the sensor in use: collision impulse ratio (Fig. 5), end-to-end
latency by cross-correlation, and zero-phase moving-average filters (Fig. 6).

- eta over latency x stiffness and latency x approach speed (closed form), checked
  against a numerical integration of the same model on a grid of parameters;
- eta against v0 at fixed f_in, beside two simplified forms;
- a simulated stream of one unit (1 kHz F/T truth, 200 Hz barometers, the unit's own
  model trained on its simulated calibration) and the delays of its processing chains;
  the eta each delay implies at the nominal collision;
- the zero-phase moving average against scipy.signal.filtfilt on that stream.

The registry is not read: the collision model is analytic and the latency stream comes
from the simulator (analysis/stream.py says why). Rows: `impulse:*`, `filter:*`,
`latency:*`; keys that have no meaning for a row are "-", 0 or None.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from pydantic import BaseModel, ConfigDict, Field
from scipy.signal import filtfilt

from anytip.analysis import budget
from anytip.analysis import impulse as imp
from anytip.analysis.filters import causal_delay_s, zero_phase_lookahead_s, zero_phase_moving_average
from anytip.analysis.latency import hold_delay_s
from anytip.analysis.stream import estimate, press_trajectory, sense, train_unit_model
from anytip.errors import AnytipError
from anytip.pipelines.common import Context, validate_options
from anytip.pipelines.impulse_ratio_report import write_report
from anytip.search.budget import cost as mcu_cost
from anytip.search.budget import load_budget
from anytip.sensor.simulate import unit_rng, unit_sensor_id
from anytip.sensor.variation import draw_unit

REGISTRY = "unused"  # how the runner treats the registry (anytip.runner)


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class Collision(Strict):
    """Nominal collision, SI units: the paper's [5 g, 0.1 kg, 7 ms, 1500 N/m, 0.15 m/s, 10 N]."""

    m_f: float = Field(imp.NOMINAL["m_f"], ge=0)
    m_r: float = Field(imp.NOMINAL["m_r"], gt=0)
    t_l: float = Field(imp.NOMINAL["t_l"], ge=0)
    k: float = Field(imp.NOMINAL["k"], gt=0)
    v0: float = Field(imp.NOMINAL["v0"], gt=0)
    f_in: float = Field(imp.NOMINAL["f_in"], ge=0)


class Latency(Strict):
    """The simulated stream and the latency budget's assumptions."""

    presses: int = Field(30, ge=2)
    truth_rate_hz: float = Field(1000.0, gt=0)
    decimate: int = Field(5, ge=1, description="truth samples per sensor sample")
    protocols: list[str] = Field(["quick", "short"], min_length=1)
    budget: str = Field("stm32f334", description="the microcontroller (configs/budgets/): clock and "
                                                 "cycles per instruction of the inference time")
    max_delay_ms: float = Field(100.0, gt=0)


class Options(Strict):
    """`options:` of an impulse_ratio spec."""

    nominal: Collision = Collision()
    map_latency_ms: tuple[float, float] = (0.0, 25.0)  # Fig. 5 axis ranges, and of the check grid
    map_stiffness_n_per_m: tuple[float, float] = (200.0, 5000.0)
    map_v0_m_per_s: tuple[float, float] = (0.05, 1.0)
    map_points: int = Field(81, ge=3)
    check_points: int = Field(7, ge=2, description="per axis of the closed-form check grid")
    v0_values: list[float] = Field([0.05, 0.1, 0.15, 0.3, 0.5, 1.0], min_length=1)
    filter_windows: list[int] = Field([7, 15], min_length=1)
    latency: Latency = Latency()


def parse_options(ctx: Context) -> Options:
    source = f"{ctx.provenance.get('spec_file', ctx.spec.name)}: options"
    opts = validate_options(ctx, Options)
    for name in ("map_latency_ms", "map_stiffness_n_per_m", "map_v0_m_per_s"):
        lo, hi = getattr(opts, name)
        if not 0 <= lo < hi or (name != "map_latency_ms" and lo <= 0):
            raise AnytipError(f"{source}.{name}: need 0 <= low < high (low > 0 but for latency), "
                              f"got {[lo, hi]}")
    if min(opts.filter_windows) < 1 or min(opts.v0_values) <= 0:
        raise AnytipError(f"{source}: filter_windows must be >= 1 and v0_values > 0, got "
                          f"{opts.filter_windows} and {opts.v0_values}")
    return opts


def _row(method: str, seed: int, **extra: Any) -> dict[str, Any]:
    """A metrics row of an analysis without a unit or calibration budget."""
    base = {"method": method, "unit": "-", "calib_samples": 0, "seed": seed,
            "force_rmse_n": None, "angle_rmse_rad": None}
    return base | extra


def collision_maps(opts: Options) -> dict[str, Any]:
    """Fig. 5: eta over (t_l, k) and (t_l, v0), axes in SI units."""
    nominal = opts.nominal.model_dump()
    t_l = np.linspace(*opts.map_latency_ms, opts.map_points) / 1e3
    k = np.linspace(*opts.map_stiffness_n_per_m, opts.map_points)
    v0 = np.linspace(*opts.map_v0_m_per_s, opts.map_points)
    return {"t_l": t_l, "k": k, "v0": v0, "eta_k": imp.eta_grid("t_l", t_l, "k", k, nominal),
            "eta_v0": imp.eta_grid("t_l", t_l, "v0", v0, nominal)}


def closed_form_check(opts: Options) -> dict[str, float]:
    """Largest |eta closed - eta numeric| over t_l x k x v0 x f_in, and of x(t) at nominal."""
    n = opts.check_points
    stiff_half_period = np.pi * np.sqrt(opts.nominal.m_r / opts.map_stiffness_n_per_m[1])
    lat_hi = max(opts.map_latency_ms[1] / 1e3, 1.2 * stiff_half_period)
    grid = [(t, k, v, f) for t in np.linspace(0.0, lat_hi, n)
            for k in np.geomspace(*opts.map_stiffness_n_per_m, n)
            for v in np.geomspace(*opts.map_v0_m_per_s, 3)
            for f in (0.0, opts.nominal.f_in, 5 * opts.nominal.f_in)]
    base = opts.nominal.model_dump()
    diff = max(abs(imp.collision_impulse_ratio(**(base | dict(t_l=t, k=k, v0=v, f_in=f)))
                   - imp.numeric_impulse_ratio(**(base | dict(t_l=t, k=k, v0=v, f_in=f))))
               for t, k, v, f in grid)
    sim = imp.simulate_collision(**base)
    x_diff = float(np.max(np.abs(imp.displacement(sim.t, **base) - sim.x)))
    closed = imp.collision(**base)
    return {"max_abs_diff": float(diff), "points": len(grid), "x_max_abs_diff_m": x_diff,
            "duration_diff_s": abs(float(closed.duration) - sim.duration), "latency_max_s": lat_hi}


def v0_study(opts: Options) -> list[dict[str, float]]:
    """eta against v0 at fixed f_in: closed form, the two simplified forms, and at f_in scaled with v0."""
    base = opts.nominal.model_dump()
    out = []
    for v0 in opts.v0_values:
        p = base | {"v0": v0}
        scaled = base | {"v0": v0, "f_in": base["f_in"] * v0 / base["v0"]}
        out.append({"v0": v0, "eta": imp.collision_impulse_ratio(**p),
                    "eta_sinusoid": float(imp.sinusoid_impulse_ratio(**p)),
                    "eta_instant_stop": float(imp.instant_stop_impulse_ratio(
                        p["m_f"], p["m_r"], p["t_l"], p["k"], p["v0"])),
                    "eta_f_in_scaled": imp.collision_impulse_ratio(**scaled),
                    "force_ratio": p["f_in"] / (v0 * np.sqrt(p["k"] * p["m_r"]))})
    return out


def inference_cost(ctx: Context, opts: Options) -> dict[str, Any]:
    """Inference time of the spec's model on the microcontroller: instructions executed by its
    float32 C export on the emulated Cortex-M4F where the cross toolchain and emulator are
    installed (else estimated, and marked so), times the budget's cycles per instruction."""
    mcu = load_budget(opts.latency.budget)
    c = mcu_cost(tuple(ctx.spec.model.sizes), mcu, activation=ctx.spec.model.activation)
    return {"instructions": c.instructions, "measured": c.measured_instructions, "macs": c.macs,
            "cycles_per_instruction": mcu.cycles_per_instruction, "clock_hz": mcu.clock_hz,
            "mcu": mcu.mcu or mcu.name, "seconds": c.cycles / mcu.clock_hz}


def latency_study(ctx: Context, opts: Options, seed: int, inference: dict[str, Any]) -> dict[str, Any]:
    """One unit's stream, its model, the delays of its chains and of its physics' parts."""
    lat = opts.latency
    unit = draw_unit(ctx.spec.fleet, unit_rng(seed, 0))
    fit, n_calib = train_unit_model(unit, lat.protocols, ctx.spec.training, seed, ctx.spec.model,
                                    unit_sensor_id(seed, 0))
    traj = press_trajectory(lat.presses, lat.truth_rate_hz, np.random.default_rng([seed, 1]))
    stream = sense(unit, traj, lat.truth_rate_hz, lat.decimate, seed)
    est = estimate(fit, stream.pressure)
    max_delay = lat.max_delay_ms / 1e3
    return {"unit": unit_sensor_id(seed, 0), "calib_samples": n_calib, "stream": stream, "est": est,
            "errors": budget.stream_errors(stream, est), "inference": inference,
            "sizes": ctx.spec.model.sizes,
            "chains": budget.measure_chains(stream, est, inference["seconds"], opts.filter_windows,
                                            max_delay),
            "physics": budget.physics_delays(unit, traj, fit, lat.truth_rate_hz, lat.decimate, seed,
                                             max_delay),
            "unit_params": {"relax_fraction": unit.relax_fraction, "relax_tau_s": unit.relax_tau_s,
                            "hysteresis": unit.hysteresis}}


def filter_check(est: np.ndarray, windows: list[int]) -> dict[int, float]:
    """Largest |zero-phase MA - filtfilt(ones(w) / w)| over the stream's five outputs, per window."""
    return {w: float(np.max(np.abs(zero_phase_moving_average(est, w)
                                   - filtfilt(np.ones(w) / w, [1.0], est, axis=0)))) for w in windows}


def latency_rows(study: dict[str, Any], opts: Options, seed: int) -> list[dict[str, Any]]:
    """One row per chain and per physics part: delay (s) and the eta it implies at the nominal collision."""
    base = opts.nominal.model_dump()
    force, angle = study["errors"]
    common = {"unit": study["unit"], "calib_samples": study["calib_samples"], "seed": seed,
              "force_rmse_n": force, "angle_rmse_rad": angle}
    rows = [{"method": f"latency:{c.name}", **common, "latency_s": c.latency_s, "online": c.online,
             "eta": imp.collision_impulse_ratio(**(base | {"t_l": max(c.latency_s, 0.0)}))}
            for c in study["chains"]]
    rows += [{"method": f"latency:physics:{name}", **common, "latency_s": d, "online": True}
             for name, d in study["physics"].items()]
    return rows


def budget_table(study: dict[str, Any], rate_hz: float) -> list[dict[str, Any]]:
    """The budget of each online chain: parts that add up, beside what was measured."""
    sensor = next(c.latency_s for c in study["chains"] if c.name == "sensor")
    parts = {"sampling (zero-order hold, half a period)": hold_delay_s(rate_hz),
             "sensor physics (measured, `sensor` chain)": sensor,
             "inference on the Cortex-M4F": study["inference"]["seconds"]}
    out = []
    for c in study["chains"]:
        if not c.online or c.name == "sensor":
            continue
        filt = causal_delay_s(c.window, rate_hz)
        out.append({"chain": c.name, **parts, "filter": filt, "sum": sum(parts.values()) + filt,
                    "measured": c.latency_s})
    return out


def run(ctx: Context) -> list[dict[str, Any]]:
    opts = parse_options(ctx)
    seed = ctx.spec.seed
    nominal = opts.nominal.model_dump()
    eta_nominal = imp.collision_impulse_ratio(**nominal)
    check = closed_form_check(opts)
    v0s = v0_study(opts)
    rows = [_row("impulse:nominal", seed, eta=eta_nominal, **nominal),
            _row("impulse:closed_vs_numeric", seed, max_abs_diff=check["max_abs_diff"],
                 grid_points=check["points"], x_max_abs_diff_m=check["x_max_abs_diff_m"])]
    rows += [_row("impulse:v0", seed, **r) for r in v0s]
    studies, inference = {}, inference_cost(ctx, opts)
    for s in ctx.spec.all_seeds:
        studies[s] = latency_study(ctx, opts, s, inference)
        rows += latency_rows(studies[s], opts, s)
    filters = filter_check(studies[ctx.spec.all_seeds[0]]["est"], opts.filter_windows)
    rows += [_row("filter:zero_phase_vs_filtfilt", seed, window=w, max_abs_diff=d,
                  lookahead_s=zero_phase_lookahead_s(w, _rate(opts)),
                  causal_delay_s=causal_delay_s(w, _rate(opts))) for w, d in filters.items()]
    ctx.provenance.update(data_source="simulator (spec fleet), registry not read",
                          latency_units={str(s): st["unit"] for s, st in studies.items()})
    write_report(ctx, opts, {"eta_nominal": eta_nominal, "check": check, "v0": v0s,
                             "maps": collision_maps(opts), "studies": studies, "filters": filters,
                             "budgets": {s: budget_table(st, _rate(opts)) for s, st in studies.items()},
                             "recipe": ctx.spec.training.name})
    return rows


def _rate(opts: Options) -> float:
    return opts.latency.truth_rate_hz / opts.latency.decimate


def summarise(rows: list[dict[str, Any]]) -> str:
    """One screen: nominal eta, the closed-form check, and each latency chain with its eta."""
    get = lambda m: next(r for r in rows if r["method"] == m)  # noqa: E731
    lines = [f"nominal eta {get('impulse:nominal')['eta']:.4f}; closed form vs numeric max |d eta| "
             f"{get('impulse:closed_vs_numeric')['max_abs_diff']:.2e}",
             f"{'latency chain':<40}{'seed':>6}{'latency [ms]':>14}{'eta':>8}"]
    for r in rows:
        if r["method"].startswith("latency:") and "eta" in r:
            lines.append(f"{r['method'][8:]:<40}{r['seed']:>6}{r['latency_s'] * 1e3:>14.2f}{r['eta']:>8.3f}")
    return "\n".join(lines)
