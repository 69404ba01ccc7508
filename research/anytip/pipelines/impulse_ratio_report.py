"""The impulse_ratio report: markdown and figures from the pipeline's results."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from anytip.analysis import impulse as imp
from anytip.analysis.filters import causal_moving_average, zero_phase_moving_average
from anytip.report import impulse_figures as figures
from anytip.report.markdown import table
from anytip.report.writer import Report

MS = 1e3


def write_report(ctx: Any, opts: Any, res: dict[str, Any]) -> Path:
    """Write figures and `report.md` into ctx.run_dir; returns the report's path."""
    out = ctx.run_dir
    _figures(out, opts, res)
    parts = [_header(ctx, opts, res), _check(res), _maps(), _v0(opts, res), _filters(opts, res),
             _latency(opts, res)]
    return Report(out).add(*parts).write(sep="\n\n")


def _figures(out: Path, opts: Any, res: dict[str, Any]) -> None:
    nominal, maps = opts.nominal.model_dump(), res["maps"]
    mark = nominal["t_l"] * MS
    figures.eta_map(maps["t_l"] * MS, maps["k"], maps["eta_k"], out / "fig5_latency_stiffness.png",
                    "latency t_l [ms]", "stiffness k [N/m]", "eta over latency and stiffness",
                    (mark, nominal["k"]))
    figures.eta_map(maps["t_l"] * MS, maps["v0"], maps["eta_v0"], out / "fig5_latency_v0.png",
                    "latency t_l [ms]", "approach speed v0 [m/s]", "eta over latency and approach speed",
                    (mark, nominal["v0"]))
    sim = imp.simulate_collision(**nominal)
    t = np.linspace(0.0, sim.duration, 400)
    w = np.sqrt(nominal["k"] / nominal["m_r"])
    t_free = np.linspace(0.0, np.pi / w, 400)
    figures.collision_trace(t, imp.displacement(t, **nominal), sim.t, sim.x, t_free,
                            nominal["v0"] / w * np.sin(w * t_free), nominal["t_l"],
                            out / "collision_trace.png", "spring compression at the nominal collision")
    study = next(iter(res["studies"].values()))
    stream, est = study["stream"], study["est"]
    rate = stream.sensor_rate_hz
    t_truth = np.arange(len(stream.truth)) / stream.truth_rate_hz
    t_est = np.arange(len(est)) / rate + study["inference"]["seconds"]
    sel_t, sel_e = (t_truth >= 2.0) & (t_truth < 5.0), (t_est >= 2.0) & (t_est < 5.0)
    w_max = max(opts.filter_windows)
    curves = {"model, 200 Hz": est[:, 2], f"causal MA {w_max}": causal_moving_average(est[:, 2], w_max),
              f"zero-phase MA {w_max} (offline)": zero_phase_moving_average(est[:, 2], w_max)}
    figures.stream_excerpt(t_truth[sel_t], stream.truth[sel_t, 2], t_est[sel_e],
                           {k: v[sel_e] for k, v in curves.items()}, out / "latency_stream.png",
                           f"unit {study['unit']}: normal force, truth and estimates")


def _header(ctx: Any, opts: Any, res: dict[str, Any]) -> str:
    n = opts.nominal
    free = float(imp.free_impulse(n.m_f, n.m_r, n.v0))
    return f"""# {ctx.spec.name}: collision impulse ratio, end-to-end latency, zero-phase filters

Collision model ([docs/analysis.md](../../docs/analysis.md)): the fingertip m_f stops at impact
(plastic), the finger m_r on a spring k keeps moving at v0; after the latency t_l the actuator pulls
it back with f_in. The collision ends when the spring first returns to rest; impulse = m_f v0 +
integral of k x dt; eta = impulse / impulse with f_in = 0. Nominal [m_f, m_r, t_l, k, v0, f_in] =
[{n.m_f * 1e3:g} g, {n.m_r:g} kg, {n.t_l * MS:g} ms, {n.k:g} N/m, {n.v0:g} m/s, {n.f_in:g} N].

**Nominal eta = {res['eta_nominal']:.4f}** (closed form): {res['eta_nominal'] * free * 1e3:.2f} mN s
against (m_f + 2 m_r) v0 = {free * 1e3:.2f} mN s without actuator."""


def _check(res: dict[str, Any]) -> str:
    c = res["check"]
    return f"""## Closed form against numerical integration

The piecewise closed form (impulse.py: sinusoid until t_l, then a shifted sinusoid about
-f_in / k, contact end at its first zero) against scipy's `solve_ivp` (DOP853, rtol 1e-11, the
actuator step as a segment boundary, an event at x = 0) on {c['points']} parameter points (t_l
from 0 to {c['latency_max_s'] * MS:.1f} ms, beyond the free half period of the stiffest spring, k and
v0 over the map ranges, f_in at 0, nominal and 5x nominal):

- max |eta closed form - eta numeric| = **{c['max_abs_diff']:.2e}**;
- at the nominal collision, max |x closed form - x numeric| over the solver's steps =
  {c['x_max_abs_diff_m']:.2e} m, contact durations differ by {c['duration_diff_s']:.2e} s.

![spring compression](collision_trace.png)"""


def _maps() -> str:
    return """## The paper's Fig. 5: eta over latency x stiffness and latency x approach speed

Other parameters at the nominal values (red star). eta = 1 to the right of the free half period
pi sqrt(m_r / k): the collision is over before the actuator acts.

![eta over latency and stiffness](fig5_latency_stiffness.png)

![eta over latency and approach speed](fig5_latency_v0.png)"""


def _v0(opts: Any, res: dict[str, Any]) -> str:
    v = res["v0"]
    body = [[r["v0"], r["force_ratio"], r["eta"], r["eta_f_in_scaled"], r["eta_sinusoid"],
             r["eta_instant_stop"]] for r in v]
    etas = [r["eta"] for r in v]
    lo, hi = min(r["v0"] for r in v), max(r["v0"] for r in v)
    n = opts.nominal
    v0_zero = n.f_in * max(np.pi * np.sqrt(n.m_r / n.k) - n.t_l, 0.0) / (n.m_f + 2 * n.m_r)
    return f"""## Is eta invariant to the approach speed?

Not with a constant f_in. The closed form depends on the parameters only through w t_l,
m_f / m_r and f_in / (v0 sqrt(k m_r)) (the actuator force over the peak spring force of a free
bounce), so a faster approach acts like a weaker actuator. At the nominal collision eta runs from
{min(etas):.3f} to {max(etas):.3f} for v0 from {lo:g} to {hi:g} m/s (f_in = {opts.nominal.f_in:g} N).
With f_in scaled in proportion to v0 it does not move (column 4: the scaling law, exact). The
"instant stop" form (the contact ends at t_l; the f_in -> infinity limit) is v0-invariant and a
lower bound; the "free sinusoid" form (x(t) stays (v0 / w) sin(w t), the actuator subtracts
f_in (pi / w - t_l)) ignores that f_in shortens the contact and is negative for v0 below
{v0_zero:.2f} m/s.

{table(['v0 [m/s]', 'f_in / (v0 sqrt(k m_r))', 'eta', 'eta, f_in ~ v0', 'free-sinusoid form',
        'instant-stop form'], body, '.3f')}"""


def _filters(opts: Any, res: dict[str, Any]) -> str:
    rate = opts.latency.truth_rate_hz / opts.latency.decimate
    body = [[w, f"{d:.1e}", (w - 1) / rate * MS, (w - 1) / 2 / rate * MS] for w, d in res["filters"].items()]
    return f"""## Zero-phase moving average (the paper's Fig. 6)

Forward-backward moving average with filtfilt's edge handling (filters.py), applied to the five
outputs of the latency stream's model at {rate:g} Hz, against `scipy.signal.filtfilt(ones(w) / w, 1, x)`:

{table(['window [samples]', 'max abs difference', 'look-ahead needed [ms]', 'causal MA delay [ms]'],
       body, '.1f')}

A zero-phase filter has no delay but needs w - 1 future samples: it cannot run online. A causal
moving average of the same window delays by (w - 1) / 2 samples (last column; measured below)."""


def _unit_section(opts: Any, res: dict[str, Any], seed: int, st: dict[str, Any]) -> str:
    nominal, s, up = opts.nominal.model_dump(), st["stream"], st["unit_params"]
    eta = lambda d: imp.collision_impulse_ratio(**(nominal | {"t_l": max(d, 0.0)}))  # noqa: E731
    chains = [[c.name, "yes" if c.online else "no (offline)", c.latency_s * MS, eta(c.latency_s)]
              for c in st["chains"]]
    physics = [[name, d * MS] for name, d in st["physics"].items()]
    budgets = [[b["chain"], *(v * MS for k, v in b.items() if k != "chain")] for b in res["budgets"][seed]]
    device = next(c for c in st["chains"] if c.name == "device")
    seconds = len(s.truth) / s.truth_rate_hz
    return f"""### Unit {st['unit']} (seed {seed})

Stream: {opts.latency.presses} random presses at random contact points, {seconds:.1f} s, F/T truth at
{s.truth_rate_hz:g} Hz, barometers at {s.sensor_rate_hz:g} Hz. The unit's model (the paper's MLP, recipe
`{res['recipe']}`) was trained on {st['calib_samples']} contact rows of its simulated calibration
({', '.join(opts.latency.protocols)} protocols); on the stream (|Fz| > 2 N) it scores
{st['errors'][0]:.3f} N and {st['errors'][1]:.3f} rad. The unit relaxes by {up['relax_fraction']:.3f}
with tau {up['relax_tau_s']:.2f} s; its hysteresis is {up['hysteresis']:.3f}.

Delays of the normal force behind the truth by cross-correlation, and the eta each implies at
the nominal collision (1: the collision is over before the actuator acts):

{table(['chain', 'online', 'latency [ms]', 'eta'], chains, '.3f')}

What the `sensor` chain's delay is made of: the simulator's effects with memory, switched off
in turn (same stream, same noise, same model):

{table(['sensor physics', 'latency [ms]'], physics, '.3f')}

Neither effect is a pure delay. Hysteresis (a release reads higher than the press at the same
force) looks like a lag; viscoelastic relaxation (a standard linear solid: the reading decays
under a held load) acts as a slight high-pass and looks like a lead. Both apparent delays depend
on how fast the force changes (here presses of 0.3 to 1.2 s).

Budget of the online chains, parts against the measurement:

{table(['chain', 'sampling [ms]', 'sensor physics [ms]', 'inference [ms]', 'filter [ms]',
        'sum [ms]', 'measured [ms]'], budgets, '.2f')}

**End-to-end latency of the device output: {device.latency_s * MS:.2f} ms, implying eta =
{eta(device.latency_s):.3f}**, against eta = {eta(nominal['t_l']):.3f} at the paper's
{nominal['t_l'] * MS:g} ms."""


def _unit_summary(opts: Any, st: dict[str, Any]) -> list[Any]:
    d = {c.name: c.latency_s for c in st["chains"]}
    eta = imp.collision_impulse_ratio(**(opts.nominal.model_dump() | {"t_l": max(d["device"], 0.0)}))
    return [st["unit"], d["sensor"] * MS, d["device"] * MS, eta,
            *(d[f"device + causal MA {w}"] * MS for w in opts.filter_windows)]


def _inference_text(study: dict[str, Any]) -> str:
    inf = study["inference"]
    how = ("executed by the model's float32 C export on the emulated Cortex-M4F (measured, "
           "`anytip.search.budget`)" if inf["measured"] else
           "estimated from the measured cost of the paper's MLP (no cross toolchain or emulator here)")
    return (f"{inf['instructions']} instructions per inference of the "
            f"{'-'.join(map(str, study['sizes']))} MLP ({inf['macs']} MACs), {how}, x "
            f"{inf['cycles_per_instruction']:g} cycles per instruction (an estimate: the emulator counts "
            f"instructions, not cycles) / {inf['clock_hz'] / 1e6:g} MHz = {inf['seconds'] * MS:.3f} ms "
            f"on the {inf['mcu']}. The barometer conversions and the bus read-out are not counted.")


def _latency(opts: Any, res: dict[str, Any]) -> str:
    first = next(iter(res["studies"].values()))
    sections = "\n\n".join(_unit_section(opts, res, seed, st) for seed, st in res["studies"].items())
    header = ["unit", "sensor [ms]", "device [ms]", "eta", *(f"device + causal MA {w} [ms]"
                                                             for w in opts.filter_windows)]
    summary = table(header, [_unit_summary(opts, st) for st in res["studies"].values()], ".3f")
    return f"""## End-to-end latency

Sampling: a 200 Hz output held until the next one is on average half a period old (2.5 ms).
Inference: {_inference_text(first)} Filters: see above.
The paper's {opts.nominal.t_l * MS:g} ms also holds communication, which this stream does not model.

Per unit (one unit per seed; eta at the nominal collision, paper's {opts.nominal.t_l * MS:g} ms: eta =
{imp.collision_impulse_ratio(**opts.nominal.model_dump()):.3f}):

{summary}

{sections}

![stream excerpt](latency_stream.png)"""
