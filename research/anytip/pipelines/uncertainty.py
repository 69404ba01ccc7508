"""Uncertainty of the per-unit baseline: heteroscedastic heads (beta-NLL), deep ensembles
(members trained as one batched model) and split conformal intervals, side by side;
then fault simulation and how well "untrustworthy" signals flag it (AUROC).

Rows of each unit: whole held-out patches are its test rows; a further set of whole
patches of the remaining rows is its conformal calibration set (exchangeable with the
test patches, since both are whole patches drawn the same way); the rest trains the
models (random validation rows drive model selection). No metric uses a row the model
trained or calibrated on.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
import torch
from pydantic import BaseModel, ConfigDict, Field
from scipy.stats import norm

from anytip.data.arrays import FleetArrays, load_arrays
from anytip.data.faults import baseline_drift, fault_suite, rest_rows
from anytip.data.registry import Registry
from anytip.data.simulated import simulate_into
from anytip.data.splits import held_out_patches
from anytip.pipelines.common import (
    OUTPUTS,
    Context,
    load,
    patch_test_mask,
    scores,
    split_validation,
    unit_tensors,
    validate_options,
)
from anytip.pipelines.cross_sensor import Options as CrossOptions
from anytip.pipelines.cross_sensor import calibrate_many, predict_rows
from anytip.pipelines.cross_sensor import prepare as cross_prepare
from anytip.report.uncertainty import write_report
from anytip.sensor.fleet import FleetConfig, NominalParams, SpreadParams
from anytip.train import conformal as cp
from anytip.train.adapt import AdapterRecipe, train_shared
from anytip.train.data import FleetBatchData
from anytip.train.detect import (
    InputNovelty,
    KnnNovelty,
    auroc,
    contiguous_windows,
    flatline,
    rest_offset,
    unit_signals,
    window_means,
)
from anytip.train.uncertainty import EnsembleFit, mixture, predict_members, train_hetero_fleet

GROUPS = {**{name: [k] for k, name in enumerate(OUTPUTS)}, "force": [0, 1, 2], "angle": [3, 4]}
CURVE_LEVELS = np.round(np.linspace(0.05, 0.99, 20), 3)


class AdaptedOptions(BaseModel):
    """The adapted shared model of `cross_sensor` on held-out units (`options.adapted`)."""

    model_config = ConfigDict(extra="forbid")

    kind: str = "input_affine+film"
    epochs: int = Field(4, ge=1, description="shared-model epochs (the spec's recipe otherwise)")
    budget: int = Field(5000, ge=1, description="labeled stream rows that fit the adapter")
    calib_rows: int = Field(5000, ge=1, description="the next stream rows: the budget's conformal set")
    prior: float = Field(10.0, ge=0)
    calibration_protocol: str | None = "short"


class Options(BaseModel):
    """`options:` of an uncertainty spec."""

    model_config = ConfigDict(extra="forbid")

    members: int = Field(5, ge=2, description="deep-ensemble members per unit")
    beta: float = Field(0.5, ge=0, le=1, description="beta-NLL exponent")
    calib_patch_fraction: float = Field(0.2, gt=0, lt=1, description="of the non-test patches")
    max_train_rows: int | None = Field(40000, ge=100, description="per unit, random subset")
    nominal: list[float] = [0.5, 0.9, 0.95]
    mapie: bool = True
    drift_pa: list[float] = [1000.0, 3000.0]
    foreign_units: int = Field(2, ge=0, description="simulated units per foreign fleet; 0 skips")
    max_detect_rows: int = Field(40000, ge=100, description="rows per unit and fault")
    # rows per detection window: 1 s and 10 s at 200 Hz (flatline and rest offset use the first)
    windows: list[int] = Field([200, 2000], min_length=1)
    adapted: AdaptedOptions | None = None  # also the adapted shared model (needs >= 3 units)


def parse_options(ctx: Context) -> Options:
    return validate_options(ctx, Options)


@dataclass
class UQSplit:
    """Per-unit training tensors, conformal calibration rows and test rows (numpy, Pa / N, rad)."""

    data: FleetBatchData
    X_cal: list[np.ndarray]
    Y_cal: list[np.ndarray]
    X_test: list[np.ndarray]
    Y_test: list[np.ndarray]
    X_fit: list[np.ndarray]  # training rows (for input novelty statistics)


def uq_split(arrays: FleetArrays, opts: Options, test_fraction: float, val_fraction: float,
             seed: int, device: torch.device) -> UQSplit:
    """Test patches, then calibration patches of the rest, then train / validation rows."""
    targets, test_mask = arrays.targets, patch_test_mask(test_fraction, seed)
    members, parts = [], {k: [] for k in ("X_cal", "Y_cal", "X_test", "Y_test", "X_fit")}
    for u, unit in enumerate(arrays.units):
        rows = np.flatnonzero(arrays.unit == u)
        test = test_mask(arrays.patch[rows], u)
        rest = rows[~test]
        cal = held_out_patches(arrays.patch[rest], opts.calib_patch_fraction, seed * 100_003 + u + 77)
        train = rest[~cal]
        rng = np.random.default_rng(seed * 7919 + u)
        if opts.max_train_rows is not None and len(train) > opts.max_train_rows:
            train = np.sort(rng.choice(train, opts.max_train_rows, replace=False))
        fit, val = split_validation(train, val_fraction, rng)
        members.append(unit_tensors(arrays, fit, val, unit))
        for key, idx in (("cal", rest[cal]), ("test", rows[test])):
            parts[f"X_{key}"].append(arrays.pressure[idx])
            parts[f"Y_{key}"].append(targets[idx].astype(np.float64))
        parts["X_fit"].append(arrays.pressure[fit])
    return UQSplit(FleetBatchData.from_units(members, device), **parts)


@dataclass
class MethodPreds:
    """One method on one unit: point predictions and scales (n, 5) on test and calibration
    rows; `kind` is 'gaussian' (mu +- z sigma) or 'conformal' (mu +- q scale)."""

    mean_t: np.ndarray
    scale_t: np.ndarray | None
    mean_c: np.ndarray
    scale_c: np.ndarray | None
    kind: str
    pooled_scores: np.ndarray | None = None  # (n, 5): calibrate on these instead of the unit's

    def interval(self, level: float, y_cal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if self.kind == "gaussian":
            return cp.interval(self.mean_t, float(norm.ppf(0.5 + level / 2)), self.scale_t)
        s = self.cal_scores(y_cal) if self.pooled_scores is None else self.pooled_scores
        return cp.interval(self.mean_t, cp.conformal_quantile(s, 1 - level), self.scale_t)

    def cal_scores(self, y_cal: np.ndarray) -> np.ndarray:
        return cp.scores_of(self.mean_c, y_cal, self.scale_c)


def add_pooled(methods: list[dict[str, MethodPreds]], Y_cal: list[np.ndarray],
               names: tuple[str, ...] = ("ensemble+conformal", "hetero+conformal")) -> None:
    """Add `<name>:pooled`: normalised scores pooled over every unit's calibration patches
    (more calibration patches per quantile; relies on sigma putting units on one scale)."""
    for name in names:
        pooled = np.concatenate([m[name].cal_scores(y) for m, y in zip(methods, Y_cal, strict=True)])
        for m in methods:
            m[f"{name}:pooled"] = replace(m[name], pooled_scores=pooled)


def unit_methods(fit: EnsembleFit, u: int, split: UQSplit) -> dict[str, MethodPreds]:
    """The compared methods on unit u. Member 0 alone is the heteroscedastic model."""
    mu_t, sig_t = predict_members(fit, u, split.X_test[u])
    mu_c, sig_c = predict_members(fit, u, split.X_cal[u])
    e_t, es_t, _ = mixture(mu_t, sig_t)
    e_c, es_c, _ = mixture(mu_c, sig_c)
    return {
        "hetero": MethodPreds(mu_t[0], sig_t[0], mu_c[0], sig_c[0], "gaussian"),
        "ensemble": MethodPreds(e_t, es_t, e_c, es_c, "gaussian"),
        "conformal": MethodPreds(mu_t[0], None, mu_c[0], None, "conformal"),
        "hetero+conformal": MethodPreds(mu_t[0], sig_t[0], mu_c[0], sig_c[0], "conformal"),
        "ensemble+conformal": MethodPreds(e_t, es_t, e_c, es_c, "conformal"),
    }


def nll(p: MethodPreds, y: np.ndarray) -> np.ndarray | None:
    """Mean Gaussian NLL per output (5,) in physical units, for Gaussian methods."""
    if p.kind != "gaussian":
        return None
    s2 = p.scale_t ** 2
    return (0.5 * (np.log(2 * np.pi * s2) + (y - p.mean_t) ** 2 / s2)).mean(0)


def method_rows(name: str, p: MethodPreds, y: np.ndarray, y_cal: np.ndarray, base: dict[str, Any],
                levels: list[float]) -> list[dict[str, Any]]:
    """One row per (nominal level, output group)."""
    rows, point, n = [], scores(p.mean_t, y), nll(p, y)
    for level in levels:
        lo, hi = p.interval(level, y_cal)
        cov, wid = cp.coverage(lo, hi, y), cp.width(lo, hi)
        for group, cols in GROUPS.items():
            rows.append({**base, "method": name, "nominal_coverage": level, "group": group,
                         "coverage": float(cov[cols].mean()), "interval_width": float(wid[cols].mean()),
                         "nll": None if n is None else float(n[cols].mean()),
                         "force_rmse_n": point["force_rmse_n"],
                         "angle_rmse_rad": point["angle_rmse_rad"]})
    return rows


def mapie_rows(p: MethodPreds, y: np.ndarray, y_cal: np.ndarray, base: dict[str, Any],
               levels: list[float]) -> list[dict[str, Any]]:
    """MAPIE's split conformal on the same residuals, and its gap to the own `conformal`."""
    rows, point = [], scores(p.mean_t, y)
    for level in levels:
        half = cp.mapie_halfwidth(p.mean_t, y_cal, p.mean_c, level)
        lo, hi = cp.interval(p.mean_t, half)
        own = cp.conformal_quantile(cp.scores_of(p.mean_c, y_cal), 1 - level)
        cov = cp.coverage(lo, hi, y)
        for group, cols in GROUPS.items():
            rows.append({**base, "method": "mapie", "nominal_coverage": level, "group": group,
                         "coverage": float(cov[cols].mean()), "interval_width": float(2 * half[cols].mean()),
                         "nll": None, "mapie_minus_own_width": float(2 * (half[cols] - own[cols]).max()),
                         "force_rmse_n": point["force_rmse_n"], "angle_rmse_rad": point["angle_rmse_rad"]})
    return rows


def curve_and_maps(methods: dict[str, MethodPreds], y: np.ndarray, y_cal: np.ndarray
                   ) -> dict[str, Any]:
    """Calibration curve per method (levels -> coverage over all outputs) and per-row
    force-coverage at nominal 0.9 (for the contact-region map and against force)."""
    curves, covered = {}, {}
    for name, p in methods.items():
        curves[name] = [float(cp.coverage(*p.interval(lv, y_cal), y).mean()) for lv in CURVE_LEVELS]
        lo, hi = p.interval(0.9, y_cal)
        covered[name] = ((y >= lo) & (y <= hi))[:, :3].mean(1)
    return {"curves": curves, "covered": covered}


def run(ctx: Context) -> list[dict[str, Any]]:
    spec, opts = ctx.spec, parse_options(ctx)
    arrays = load(ctx)
    rows: list[dict[str, Any]] = []
    fig: dict[str, Any] = {"curves": [], "covered": [], "angles": [], "force": []}
    for seed in spec.all_seeds:
        split = uq_split(arrays, opts, spec.splits.patch_test_fraction, spec.splits.val_fraction,
                         seed, ctx.device)
        fit = train_hetero_fleet(split.data, spec.model, spec.training, opts.members, opts.beta,
                                 seed, ctx.device)
        fit.save(ctx.run_dir / "models" / f"hetero_ensemble_seed{seed}")
        ctx.provenance.setdefault("train_s", []).append(round(fit.wall_s, 1))
        all_methods = [unit_methods(fit, u, split) for u in range(len(arrays.units))]
        add_pooled(all_methods, split.Y_cal)
        for u, unit in enumerate(arrays.units):
            base = {"unit": unit, "seed": seed, "calib_samples": int(split.data.n_train[u]),
                    "conformal_rows": len(split.Y_cal[u]), "test_rows": len(split.Y_test[u])}
            y, y_cal, methods = split.Y_test[u], split.Y_cal[u], all_methods[u]
            for name, p in methods.items():
                rows += method_rows(name, p, y, y_cal, base, opts.nominal)
            if opts.mapie:
                rows += mapie_rows(methods["conformal"], y, y_cal, base, opts.nominal)
            if seed == spec.all_seeds[0]:
                maps = curve_and_maps(methods, y, y_cal)
                fig["curves"].append(maps["curves"])
                fig["covered"].append(maps["covered"])
                fig["angles"].append(y[:, 3:])
                fig["force"].append(np.linalg.norm(y[:, :3], axis=1))
        rows += fault_rows(ctx, arrays, fit, split, opts, seed)
        if opts.adapted is not None:
            rows += adapted_rows(ctx, arrays, opts.adapted, opts.nominal, seed)
    write_report(ctx, rows, fig, opts, CURVE_LEVELS)
    return rows


def foreign_fleets(spec_fleet: FleetConfig) -> dict[str, FleetConfig]:
    """Units no training unit resembles: stronger casting defects (3x direction defects,
    4x bubble chance, stronger voids), and another sensor model (stiffer rubber, weaker
    coupling, larger indenter, stronger direction coupling)."""
    s = spec_fleet.spread
    strong = SpreadParams(**{**s.model_dump(), "direction_defect_sigma": 3 * s.direction_defect_sigma,
                             "bubble_probability": min(1.0, 4 * s.bubble_probability),
                             "bubble_strength_max": 0.9})
    n = spec_fleet.nominal
    other = NominalParams(**{**n.model_dump(), "modulus_pa": 2 * n.modulus_pa, "coupling_gain": 0.8,
                             "indenter_radius_m": 1.2 * n.indenter_radius_m, "direction_coupling": 0.5})
    return {"strong_defects_unit": spec_fleet.model_copy(update={"spread": strong}),
            "other_sensor_model": spec_fleet.model_copy(update={"sensor_model": "fingertip-other",
                                                                "nominal": other})}


def foreign_pressures(ctx: Context, opts: Options, seed: int, root: Path) -> dict[str, np.ndarray]:
    """Tared pressures (n, C) of simulated foreign units, read back through registries
    under `root` (the same path as any other data; the configs are in foreign_fleets)."""
    out = {}
    for k, (name, cfg) in enumerate(foreign_fleets(ctx.spec.fleet).items()):
        reg = Registry(root / f"{name}_seed{seed}")
        simulate_into(reg, cfg, opts.foreign_units, seed=10_000 + 97 * seed + k, protocols=("short",))
        out[name] = load_arrays(reg, reg.list_runs()).pressure
    return out


def fault_rows(ctx: Context, arrays: FleetArrays, fit: EnsembleFit, split: UQSplit, opts: Options,
               seed: int) -> list[dict[str, Any]]:
    """AUROC of every signal for every fault on every unit, per row and per window: clean
    test rows against the same rows with the fault injected (or a foreign unit's rows
    through this unit's model). Rows are whole windows of consecutive test rows."""
    with tempfile.TemporaryDirectory() as tmp:
        foreign = foreign_pressures(ctx, opts, seed, Path(tmp)) if opts.foreign_units else {}
    rows = []
    for u, unit in enumerate(split.data.unit_ids):
        rng = np.random.default_rng(seed * 31 + u)
        pick = contiguous_windows(len(split.X_test[u]), max(opts.windows), opts.max_detect_rows, rng)
        x = split.X_test[u][pick]
        novelty = (InputNovelty.fit(split.X_fit[u]), KnnNovelty.fit(split.X_fit[u], seed=seed))
        faults = fault_suite(x, split.X_fit[u], rng, opts.drift_pa) | {
            k: v[contiguous_windows(len(v), max(opts.windows), opts.max_detect_rows, rng)]
            for k, v in foreign.items()}
        clean = _signals(fit, u, x, novelty)
        base = {"unit": unit, "seed": seed, "calib_samples": int(split.data.n_train[u]),
                "force_rmse_n": None, "angle_rmse_rad": None}
        for fault, xf in faults.items():
            bad = _signals(fit, u, xf, novelty)
            changed = (xf != x).any(1) if fault == "saturation" else slice(None)
            for signal in clean:
                for w in (1, *opts.windows):
                    c = window_means(clean[signal][changed], w)
                    b = window_means(bad[signal][changed], w)
                    if len(b) == 0 or (fault == "saturation" and w > 1):
                        continue
                    rows.append({**base, "method": f"detect:{signal}", "fault": fault, "window": w,
                                 "fault_rows": len(xf), "auroc": auroc(c, b)})
            if fault != "saturation":
                rows.append({**base, "method": "detect:flatline", "fault": fault, "window": opts.windows[0],
                             "fault_rows": len(xf), "auroc": auroc(flatline(x, opts.windows[0]),
                                                                   flatline(xf, opts.windows[0]))})
        rows += rest_drift_rows(ctx, arrays, u, opts, rng, base)
    return rows


def rest_drift_rows(ctx: Context, arrays: FleetArrays, u: int, opts: Options,
                    rng: np.random.Generator, base: dict[str, Any]) -> list[dict[str, Any]]:
    """Baseline drift judged where a deployed unit sees it best: its contact-free rows
    between touches (never used for training or tare), clean against offset."""
    rest = rest_rows(ctx.registry, [r for r in arrays.runs if r.unit == arrays.units[u]])
    if len(rest) < 2 * opts.windows[0]:
        return []
    ch = np.array([int(rng.integers(rest.shape[1]))])
    clean, rows = rest_offset(rest, opts.windows[0]), []
    for a in opts.drift_pa:
        for name, chans in ((f"drift_all_{a / 1000:g}kPa", None), (f"drift_one_{a / 1000:g}kPa", ch)):
            bad = rest_offset(baseline_drift(rest, a, chans), opts.windows[0])
            rows.append({**base, "method": "detect:rest_offset", "fault": name, "window": opts.windows[0],
                         "fault_rows": len(rest), "auroc": auroc(clean, bad)})
    return rows


def _signals(fit: EnsembleFit, u: int, x: np.ndarray,
             novelty: tuple[InputNovelty, KnnNovelty]) -> dict[str, np.ndarray]:
    mu, sigma = predict_members(fit, u, x)
    return unit_signals(mu, sigma, fit.out_scaler.std[u, 0].cpu().numpy(),
                        {"novelty": novelty[0](x), "knn_novelty": novelty[1](x)})


def summarise(rows: list[dict[str, Any]]) -> str:
    """Coverage at nominal 0.9 per method (min / mean / max over units, force and angle)."""
    lines = [f"{'method':<46}{'group':<7}{'min':>7}{'mean':>7}{'max':>7}{'width':>9}"]
    keyed: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in rows:
        if r.get("nominal_coverage") == 0.9 and r.get("group") in ("force", "angle"):
            keyed.setdefault((r["method"], r["group"]), []).append(r)
    for (method, group), rs in keyed.items():
        c = [r["coverage"] for r in rs]
        lines.append(f"{method:<46}{group:<7}{min(c):>7.3f}{np.mean(c):>7.3f}{max(c):>7.3f}"
                     f"{np.mean([r['interval_width'] for r in rs]):>9.3f}")
    return "\n".join(lines)


def adapted_rows(ctx: Context, arrays: FleetArrays, a: AdaptedOptions, levels: list[float],
                 seed: int) -> list[dict[str, Any]]:
    """Split conformal for the adapted shared model on held-out units, two ways:
    `val_units`: absolute residuals of the validation units (their own adapters, on their
    held-out patches), pooled; `budget`: the held-out unit's own calibration stream, the
    `calib_rows` rows after the `budget` rows that fitted its adapter. Scored on the
    held-out units' test patches, which neither touches."""
    co = CrossOptions(calibration_protocol=a.calibration_protocol, priors=[a.prior], adapters=[a.kind],
                      sweep_adapter=a.kind)
    sd = cross_prepare(ctx, arrays, co, seed)
    recipe = ctx.spec.training.model_copy(update={"epochs": a.epochs})
    shared = train_shared(sd.train, sd.train_stats, ctx.spec.model, a.kind, recipe, seed, ctx.device,
                          adapter_decay=co.adapter_decay)
    units = [*sd.split.val, *sd.split.test]
    streams = [sd.evals[u].stream for u in units]
    folded, stats = calibrate_many(shared, arrays, streams, [a.budget] * len(units), [a.prior] * len(units),
                                   AdapterRecipe(co.adapter_steps, co.adapter_lr), seed)
    test = [sd.evals[u].test_rows for u in units]
    cal = [st.rows[a.budget:a.budget + a.calib_rows] for st in streams]
    pred_t = predict_rows(folded, stats, shared.out_scaler, arrays, test)
    some = [c if len(c) else t[:1] for c, t in zip(cal, test, strict=True)]  # empty: no budget variant
    pred_c = predict_rows(folded, stats, shared.out_scaler, arrays, some)
    y = arrays.targets.astype(np.float64)
    n_val = len(sd.split.val)
    pooled = np.concatenate([np.abs(pred_t[m] - y[test[m]]) for m in range(n_val)])
    rows, name = [], f"adapted:{a.kind}+conformal"
    for m in range(n_val, len(units)):
        base = {"unit": units[m], "seed": seed, "calib_samples": a.budget,
                "n_train_units": len(sd.split.train), "test_rows": len(test[m])}
        p = MethodPreds(pred_t[m], None, pred_c[m], None, "conformal")
        rows += method_rows(f"{name}:val_units", replace(p, pooled_scores=pooled), y[test[m]], y[:0],
                            {**base, "conformal_rows": len(pooled)}, levels)
        if len(cal[m]):
            rows += method_rows(f"{name}:budget", p, y[test[m]], y[cal[m]],
                                {**base, "conformal_rows": len(cal[m])}, levels)
    return rows
