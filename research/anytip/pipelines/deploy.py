"""Deployment: models exported to ONNX, C (float32, int8) and the firmware struct, verified and
measured on a Cortex-M4F, beside the same models exported by emlearn and emx-onnx-cgen.

Each `models` entry names a per-unit model file and a unit; each `calibrate` entry first runs
`anytip calibrate` (a shared cross-sensor model, a new unit, a label budget) and exports the folded
model it saves. Every format and peer gives one result row with its flash, RAM, executed
instructions, max error against the trained model and RMSE on the unit's reference rows (its
held-out patches when `held_out` names the cross_sensor run that recorded them).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from pydantic import BaseModel, ConfigDict

from anytip.deploy.export import Prepared, export_prepared, prepare
from anytip.deploy.held_out import HeldOut as HeldOutRows
from anytip.deploy.held_out import from_run as held_out_from_run
from anytip.deploy.native import fma_flags
from anytip.deploy.peers import PEERS, measure_peer
from anytip.errors import AnytipError
from anytip.pipelines.common import Context, validate_options
from anytip.report.markdown import table
from anytip.report.writer import Report
from anytip.rundir import write_json

REGISTRY = "optional"  # how the runner treats the registry (anytip.runner)

FORMATS = ("onnx", "c", "c-int8", "firmware")


class ModelEntry(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)
    name: str
    path: str
    unit: str | None = None


class CalibrateEntry(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)
    name: str
    shared: str
    unit: str
    budget_samples: int = 1000


class HeldOut(BaseModel):
    """Score on a unit's held-out patches as a cross_sensor (or baseline) run drew them."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)
    run: str  # a cross_sensor or baseline run directory
    seed: int
    protocols: list[str] = ["full"]  # runs whose rows are scored (not the calibration protocol)


class Options(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)
    held_out: HeldOut | None = None
    models: list[ModelEntry] = []
    calibrate: list[CalibrateEntry] = []
    formats: list[str] = list(FORMATS)
    peers: list[str] = list(PEERS)
    rows: int = 20000


def parse_options(ctx: Context) -> Options:
    opts = validate_options(ctx, Options)
    bad = [f for f in opts.formats if f not in FORMATS] + [p for p in opts.peers if p not in PEERS]
    if bad:
        raise AnytipError(f"options: unknown formats or peers {bad}; formats are {list(FORMATS)}, "
                          f"peers {list(PEERS)}")
    if not opts.models and not opts.calibrate:
        raise AnytipError("options: give at least one entry under options.models or options.calibrate")
    return opts


def _models(ctx: Context, opts: Options) -> list[tuple[str, str, str | None, int]]:
    """(name, model path, unit, calibration samples) per entry; calibrate entries are run first."""
    from anytip.calibrate import calibrate_unit

    out = [(m.name, m.path, m.unit, 0) for m in opts.models]
    for c in opts.calibrate:
        if not ctx.registry.list_runs(unit=c.unit):
            ctx.provenance.setdefault("deploy_skipped", []).append(
                f"{c.name}: the registry has no runs of unit {c.unit}, so nothing to calibrate")
            continue
        cal = calibrate_unit(c.shared, c.unit, ctx.registry, ctx.run_dir / "calibrated" / c.name,
                             budget_samples=c.budget_samples)
        out.append((c.name, str(cal.path), c.unit, cal.calib_samples))  # holds model.safetensors
    return out


def _held_out(opts: Options, unit: str | None, registry) -> HeldOutRows | str:
    """The unit's held-out rows of options.held_out, or "auto" (what the model file tells)."""
    h = opts.held_out
    if h is None or unit is None:
        return "auto"
    rows = held_out_from_run(h.run, h.seed, unit, registry=registry)
    rows.protocols = list(h.protocols)
    return rows


def _row(name: str, method: str, p: Prepared, samples: int, seed: int, rep: dict[str, Any]) -> dict[str, Any]:
    check = next((rep[k] for k in ("onnxruntime", "gcc_host", "firmware_direct") if k in rep), None)
    if "int8_vs_float_max_abs_err" in rep:  # int8: its distance from the float model, for information
        d = np.asarray(rep["int8_vs_float_max_abs_err"]) / p.net.out_scale
        check = {"max_rel_err": float(d.max())}
    m4 = rep.get("cortex_m4") or {}
    sc = rep.get("scores") or {}
    return {"method": method, "model": name, "unit": p.net.unit, "calib_samples": samples, "seed": seed,
            "force_rmse_n": sc.get("force_rmse_n", float("nan")),
            "angle_rmse_rad": sc.get("angle_rmse_rad", float("nan")),
            "max_rel_err": None if check is None else check["max_rel_err"],
            "err_over_bound": None if check is None else check.get("max_err_over_bound"),
            "int8_rmse_increase": (rep.get("accuracy") or {}).get("rmse_increase"),
            "flash_bytes": m4.get("flash_bytes"), "ram_bytes": m4.get("ram_bytes"),
            "instructions": m4.get("instructions"), "instructions_per_mac": m4.get("instructions_per_mac"),
            "macs": p.net.macs, "passed": rep.get("passed"), "reference": p.ref.source,
            "skipped": rep.get("skipped") or m4.get("skipped") or m4.get("emulator_skipped")}


def run(ctx: Context) -> list[dict[str, Any]]:
    opts = parse_options(ctx)
    rows: list[dict[str, Any]] = []
    for name, path, unit, samples in _models(ctx, opts):
        p = prepare(path, unit, ctx.registry, opts.rows, _held_out(opts, unit, ctx.registry))
        out = ctx.run_dir / "exports" / name
        for fmt in opts.formats:
            rep = export_prepared(p, fmt, out / fmt)
            rows.append(_row(name, f"anytip_{fmt.replace('-', '_')}", p, samples, ctx.spec.seed, rep))
        for peer in opts.peers:
            rep = measure_peer(peer, p.loaded, p.index, p.net, p.ref, p.y_model, out / peer)
            rep["passed"] = bool(rep.get("gcc_host", {}).get("passed"))
            (out / peer).mkdir(parents=True, exist_ok=True)
            write_json(out / peer / "verification.json", rep)
            rows.append(_row(name, peer.replace("-", "_"), p, samples, ctx.spec.seed, rep))
    Report(ctx.run_dir).add(report(rows, ctx.provenance.get("deploy_skipped", []))).write()
    return rows


def _fmt(v: Any, spec: str = ",") -> str:
    if v is None:
        return "-"
    if isinstance(v, float) and v != v:
        return "-"
    return format(v, spec)


def report(rows: list[dict[str, Any]], skipped: list[str]) -> str:
    """Markdown: one table per model, formats and peers side by side."""
    parts = ["# Deployment: exports verified and measured on a Cortex-M4F", "",
             "Flash = text + rodata + data and RAM = data + bss + stack of one `anytip_infer` call, "
             "cross-compiled with arm-none-eabi-gcc -O2 for Cortex-M4F (fpv4-sp-d16, hard float, "
             "fused multiply-add). Instructions: one inference executed on the unicorn emulator "
             "(Cortex-M4 CPU model). Max rel. err: max abs difference from the trained model "
             "(float64) over the reference rows, divided by the output's scale, with the float C "
             f"built here by gcc {' '.join(fma_flags()) or '(no fused multiply-add on this CPU)'} so "
             "that it sums like the Cortex-M4F build. Err/bound: the largest ratio, over rows and "
             "outputs, of that error to the float32 rounding error bound of the exported network on "
             "the row (docs/deploy.md#verification). Float exports and peers are verified when it is "
             "<= 1 and anytip's files hold the float32 parameters bit for bit (int8: verified when its "
             "C equals its numpy model within one last-layer activation step and the RMSE increase "
             "over float is within 2%). RMSE on the scored reference "
             "rows: 'registry, held out' rows are rows the model never trained on (options.held_out, or what "
             "the model file's run directory or metadata tell); plain 'registry' rows may include "
             "training rows.", ""]
    for name in dict.fromkeys(r["model"] for r in rows):
        rs = [r for r in rows if r["model"] == name]
        parts += [f"## {name} (unit {rs[0]['unit']}, {rs[0]['macs']} MACs, reference rows: "
                  f"{rs[0]['reference']})", ""]
        body = [[r["method"], _fmt(r["flash_bytes"]), _fmt(r["ram_bytes"]), _fmt(r["instructions"]),
                 _fmt(r["instructions_per_mac"], ".2f"), _fmt(r["max_rel_err"], ".1e"),
                 _fmt(r.get("err_over_bound"), ".2g"), _fmt(r["force_rmse_n"], ".4f"),
                 _fmt(r["angle_rmse_rad"], ".5f"),
                 "yes" if r["passed"] else "NO"] for r in rs]
        parts += [table(["method", "flash B", "RAM B", "instructions", "instr/MAC", "max rel. err",
                         "err/bound", "force RMSE N", "angle RMSE rad", "verified"], body), ""]
        inc = next((r["int8_rmse_increase"] for r in rs if r["int8_rmse_increase"]), None)
        if inc:
            parts += [f"int8 RMSE increase over float32: force {inc['force_rmse_n']:+.2%}, angle "
                      f"{inc['angle_rmse_rad']:+.2%} (target: within 2%).", ""]
    if skipped:
        parts += ["Skipped: " + "; ".join(skipped), ""]
    return "\n".join(parts)


def summarise(rows: list[dict[str, Any]]) -> str:
    lines = [f"{'model':<22}{'method':<18}{'flash B':>9}{'RAM B':>7}{'instr':>8}{'i/MAC':>7}{'rel err':>10}"]
    for r in rows:
        lines.append(f"{r['model']:<22}{r['method']:<18}{_fmt(r['flash_bytes']):>9}{_fmt(r['ram_bytes']):>7}"
                     f"{_fmt(r['instructions']):>8}{_fmt(r['instructions_per_mac'], '.2f'):>7}"
                     f"{_fmt(r['max_rel_err'], '.1e'):>10}")
    return "\n".join(lines)
