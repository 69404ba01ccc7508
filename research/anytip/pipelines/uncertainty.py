"""Uncertainty of the per-unit baseline: heteroscedastic heads (beta-NLL), deep ensembles
(members trained as one batched model) and split conformal intervals, side by side;
then fault simulation and how well "untrustworthy" signals flag it (AUROC; in
pipelines/uncertainty_faults.py).

Rows of each unit: whole held-out patches are its test rows; a further set of whole
patches of the remaining rows is its conformal calibration set (exchangeable with the
test patches, since both are whole patches drawn the same way); the rest trains the
models (random validation rows drive model selection). No metric uses a row the model
trained or calibrated on.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from scipy.stats import norm

from anytip.data.arrays import FleetArrays, has_patch_grid, output_names, target_slices
from anytip.data.plans import stream_plan
from anytip.data.runfile import V1_LAYOUT, TargetLayout
from anytip.data.seeds import (
    BOOTSTRAP,
    ENSEMBLE_MEMBER,
    FOLD_MODEL,
    FOLD_ROWS,
    PATCH_FOLDS,
    UNSEEN_ROWS,
    stream_seed,
)
from anytip.errors import AnytipError
from anytip.models.heteroscedastic import output_scaler_2d
from anytip.models.io import save_models
from anytip.models.mlp import BatchedMLP
from anytip.models.scaler import Scaler
from anytip.pipelines.common import Context, load, validate_options
from anytip.pipelines.cross_sensor import prepare as cross_prepare
from anytip.pipelines.cross_sensor_options import Options as CrossOptions
from anytip.pipelines.uncertainty_faults import fault_rows
from anytip.pipelines.uncertainty_options import AdaptedOptions, Options
from anytip.report.uncertainty import BAND, is_target, write_report
from anytip.train.adapt import AdapterRecipe, SharedFit, train_shared
from anytip.train.data import FleetBatchData, split_validation, unit_tensors
from anytip.train.metrics import scores, target_keys
from anytip.train.shared_split import calibrate_many, predict_rows
from anytip.uncertainty import conformal as cp
from anytip.uncertainty import coverage_bootstrap as boot
from anytip.uncertainty.costs import embedded_costs
from anytip.uncertainty.cross_conformal import out_of_fold, patch_folds, pick_fold_model
from anytip.uncertainty.ensembles import (
    EnsembleFit,
    hetero_meta,
    mixture,
    predict_members,
    train_hetero_fleet,
)
from anytip.uncertainty.shared_scale import (
    fit_force_scale,
    fit_scale_network,
    force_scale,
    predict_scale,
    shared_residuals,
)
from anytip.uncertainty.split import UQSplit, capped, uq_split

TARGET_NAMES = {"angles": "angle"}  # the fingertip's rows name its angle group `angle`


def output_groups(layout: dict[str, TargetLayout]) -> dict[str, list[int]]:
    """Coverage groups of a layout: each label column by its component name, then each target
    over its columns (the fingertip's: fx ... phi, force, angle)."""
    names = output_names(layout)
    cols = {name: [k] for k, name in enumerate(names)}
    for target, sl in target_slices(layout).items():
        cols[TARGET_NAMES.get(target, target)] = list(range(sl.start, sl.stop))
    return cols


def target_groups(layout: dict[str, TargetLayout]) -> list[str]:
    """The group names that are whole targets (the fingertip's: force, angle)."""
    return [TARGET_NAMES.get(t, t) for t in layout]
CURVE_LEVELS = np.round(np.linspace(0.05, 0.99, 20), 3)


def parse_options(ctx: Context) -> Options:
    return validate_options(ctx, Options)


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


def add_cross_conformal(ctx: Context, arrays: FleetArrays, split: UQSplit, opts: Options, seed: int,
                        methods: list[dict[str, MethodPreds]]) -> None:
    """Add `cv+conformal` (absolute residual) and `cv+hetero+conformal` (normalised):
    K fold models per unit, trained as one batched heteroscedastic fleet of U * K models,
    each on the unit's non-test patches outside its fold; q from every non-test row's
    out-of-fold score; each test row scored with a fold model drawn at random
    (`anytip.uncertainty.cross_conformal`)."""
    K, members, folds = opts.cv_folds, [], []
    for u, unit in enumerate(arrays.units):
        rest = split.rest_idx[u]
        n_patches = len(np.unique(arrays.patch[rest]))
        if K < 2 or n_patches < K:
            raise AnytipError(f"options.cv_folds={K}: needs 2 or more folds and at most the {n_patches} "
                              f"non-test patches of unit {unit}; use 0 to skip cross-conformal")
        fold = patch_folds(arrays.patch[rest], K, stream_seed(PATCH_FOLDS, seed, u))
        folds.append(fold)
        for k in range(K):
            rng = np.random.default_rng(stream_seed(FOLD_ROWS, seed, 31 * u + k))
            train = capped(rest[fold != k], opts.max_train_rows, rng)
            members.append(unit_tensors(arrays, *split_validation(train, ctx.spec.splits.val_fraction, rng),
                                        f"{unit}/fold{k}"))
    data = FleetBatchData.from_units(members, ctx.device, arrays.output_names)
    fit = train_hetero_fleet(data, ctx.spec.model, ctx.spec.training, 1, opts.beta, seed, ctx.device)
    ctx.provenance.setdefault("cv_train_s", []).append(round(fit.wall_s, 1))
    y = arrays.targets.astype(np.float64)
    for u in range(len(arrays.units)):
        rest = split.rest_idx[u]
        pred_r, pred_t = [], []
        for k in range(K):
            for out, x in ((pred_r, arrays.pressure[rest]), (pred_t, split.X_test[u])):
                m, s = predict_members(fit, u * K + k, x)
                out.append((m[0], s[0]))
        mu_t, sig_t = pick_fold_model(pred_t, np.random.default_rng(stream_seed(FOLD_MODEL, seed, u)))
        mu_c, sig_c = out_of_fold(pred_r, folds[u])
        for name, st, sc in (("cv+conformal", None, None), ("cv+hetero+conformal", sig_t, sig_c)):
            methods[u][name] = MethodPreds(mu_t, st, mu_c, sc, "conformal",
                                           pooled_scores=cp.scores_of(mu_c, y[rest], sc))


def nll(p: MethodPreds, y: np.ndarray) -> np.ndarray | None:
    """Mean Gaussian NLL per output (5,) in physical units, for Gaussian methods."""
    if p.kind != "gaussian":
        return None
    s2 = p.scale_t ** 2
    return (0.5 * (np.log(2 * np.pi * s2) + (y - p.mean_t) ** 2 / s2)).mean(0)


def method_rows(name: str, p: MethodPreds, y: np.ndarray, y_cal: np.ndarray, base: dict[str, Any],
                levels: list[float], patches: np.ndarray | None = None, n_boot: int = 0,
                seed: int = 0, layout: dict[str, TargetLayout] = V1_LAYOUT) -> list[dict[str, Any]]:
    """One row per (nominal level, output group of `layout`). Given the test rows' patch ids (n,)
    and n_boot > 0, `coverage_sd` is the spread of the group's coverage over test patches drawn
    again with replacement (how well the test set pins this unit's coverage down)."""
    rows, n = [], nll(p, y)
    point = {k: v for k, v in scores(p.mean_t, y, layout).items() if k in target_keys(layout)}
    whole = target_groups(layout)
    rng = np.random.default_rng(seed)
    for level in levels:
        lo, hi = p.interval(level, y_cal)
        cov, wid = cp.coverage(lo, hi, y), cp.width(lo, hi)
        boots = (boot.bootstrap_test_patches((y >= lo) & (y <= hi), patches, n_boot, rng)
                 if patches is not None and n_boot else None)
        for group, cols in output_groups(layout).items():
            extra = {} if boots is None else {"coverage_sd": float(boots[:, cols].mean(1).std())}
            rows.append({**base, "method": name, "nominal_coverage": level, "group": group,
                         "target_group": group in whole,
                         "coverage": float(cov[cols].mean()), "interval_width": float(wid[cols].mean()),
                         "nll": None if n is None else float(n[cols].mean()), **point, **extra})
    return rows


def mapie_rows(p: MethodPreds, y: np.ndarray, y_cal: np.ndarray, base: dict[str, Any],
               levels: list[float], layout: dict[str, TargetLayout] = V1_LAYOUT) -> list[dict[str, Any]]:
    """MAPIE's split conformal on the same residuals, and its gap to the own `conformal`."""
    rows = []
    point = {k: v for k, v in scores(p.mean_t, y, layout).items() if k in target_keys(layout)}
    whole = target_groups(layout)
    for level in levels:
        half = cp.mapie_halfwidth(p.mean_t, y_cal, p.mean_c, level)
        lo, hi = cp.interval(p.mean_t, half)
        own = cp.conformal_quantile(cp.scores_of(p.mean_c, y_cal), 1 - level)
        cov = cp.coverage(lo, hi, y)
        for group, cols in output_groups(layout).items():
            rows.append({**base, "method": "mapie", "nominal_coverage": level, "group": group,
                         "target_group": group in whole,
                         "coverage": float(cov[cols].mean()), "interval_width": float(2 * half[cols].mean()),
                         "nll": None, "mapie_minus_own_width": float(2 * (half[cols] - own[cols]).max()),
                         **point})
    return rows


BOOTSTRAP_METHODS = ("conformal", "hetero+conformal", "ensemble+conformal")


def bootstrap_rows(methods: dict[str, MethodPreds], y: np.ndarray, y_cal: np.ndarray, patch_t: np.ndarray,
                   patch_c: np.ndarray, base: dict[str, Any], n_boot: int, seed: int,
                   level: float = 0.9, layout: dict[str, TargetLayout] = V1_LAYOUT) -> list[dict[str, Any]]:
    """Patch-bootstrap spread of one unit's coverage at `level`, per output, for a method
    that is exactly calibrated: test patches drawn again (`test`), and calibration patches
    too (`test+calibration`, the conformal methods)."""
    rng, rows = np.random.default_rng(seed), []
    for name in BOOTSTRAP_METHODS:
        p = methods[name]
        lo, hi = p.interval(level, y_cal)
        covered = (y >= lo) & (y <= hi)
        observed = covered.mean(0)
        resid = np.abs(y - p.mean_t)
        boots = {"test": boot.bootstrap_test_patches(covered, patch_t, n_boot, rng),
                 "test+calibration": boot.conformal_patch_bootstrap(
                     p.cal_scores(y_cal), patch_c, p.scale_t, resid, patch_t, level, n_boot, rng)}
        for kind, b in boots.items():
            band = boot.exact_method_band(b, observed, level, BAND)
            for k, out in enumerate(output_names(layout)):
                rows.append({**base, "method": name, "group": out, "bootstrap": kind,
                             **dict.fromkeys(target_keys(layout)),
                             "bootstrap_level": level, "observed": float(observed[k]),
                             **{f"exact_{key}": float(v[k]) for key, v in band.items()},
                             "test_patches": len(np.unique(patch_t)), "cal_patches": len(np.unique(patch_c))})
    return rows


def curve_and_maps(methods: dict[str, MethodPreds], y: np.ndarray, y_cal: np.ndarray,
                   first: slice = slice(0, 3)) -> dict[str, Any]:
    """Calibration curve per method (levels -> coverage over all outputs) and per-row coverage
    of the first target's columns `first` at nominal 0.9 (the fingertip's force, for the
    contact-region map and against force)."""
    curves, covered = {}, {}
    for name, p in methods.items():
        curves[name] = [float(cp.coverage(*p.interval(lv, y_cal), y).mean()) for lv in CURVE_LEVELS]
        lo, hi = p.interval(0.9, y_cal)
        covered[name] = ((y >= lo) & (y <= hi))[:, first].mean(1)
    return {"curves": curves, "covered": covered}


def run(ctx: Context) -> list[dict[str, Any]]:
    spec, opts = ctx.spec, parse_options(ctx)
    arrays = load(ctx)
    rows: list[dict[str, Any]] = []
    fig: dict[str, Any] = {"curves": [], "covered": [], "angles": [], "force": []}
    fingertip = has_patch_grid(arrays.layout)
    for seed in spec.all_seeds:
        split = uq_split(arrays, opts.max_train_rows, opts.calib_patch_fraction,
                         spec.splits.patch_test_fraction, spec.splits.val_fraction, seed, ctx.device)
        fit = train_hetero_fleet(split.data, spec.model, spec.training, opts.members, opts.beta,
                                 seed, ctx.device)
        fit.save(ctx.run_dir / "models" / f"hetero_ensemble_seed{seed}")
        ctx.provenance.setdefault("train_s", []).append(round(fit.wall_s, 1))
        all_methods = [unit_methods(fit, u, split) for u in range(len(arrays.units))]
        add_pooled(all_methods, split.Y_cal)
        if opts.cv_folds:
            add_cross_conformal(ctx, arrays, split, opts, seed, all_methods)
        for u, unit in enumerate(arrays.units):
            base = {"unit": unit, "seed": seed, "calib_samples": int(split.data.n_train[u]),
                    "conformal_rows": len(split.Y_cal[u]), "test_rows": len(split.Y_test[u])}
            y, y_cal, methods = split.Y_test[u], split.Y_cal[u], all_methods[u]
            for name, p in methods.items():
                rows += method_rows(name, p, y, y_cal, base, opts.nominal, layout=arrays.layout)
            if opts.mapie:
                rows += mapie_rows(methods["conformal"], y, y_cal, base, opts.nominal, arrays.layout)
            if opts.bootstrap:
                rows += bootstrap_rows(methods, y, y_cal, arrays.patch[split.test_idx[u]],
                                       arrays.patch[split.cal_idx[u]], base, opts.bootstrap,
                                       stream_seed(BOOTSTRAP, seed, u),
                                       layout=arrays.layout)
            if seed == spec.all_seeds[0]:
                maps = curve_and_maps(methods, y, y_cal, next(iter(arrays.slices.values())))
                fig["curves"].append(maps["curves"])
                fig["covered"].append(maps["covered"])
                if fingertip:
                    fig["angles"].append(y[:, 3:])
                    fig["force"].append(np.linalg.norm(y[:, :3], axis=1))
        rows += fault_rows(ctx, arrays, fit, split, opts, seed, target_keys(arrays.layout))
        if opts.adapted is not None:
            rows += adapted_rows(ctx, arrays, opts.adapted, opts.nominal, seed, opts.beta, opts.bootstrap)
    write_report(ctx, rows, fig, opts, CURVE_LEVELS, embedded_costs(tuple(spec.model.sizes)))
    return rows


def summarise(rows: list[dict[str, Any]]) -> str:
    """Coverage at nominal 0.9 per method (min / mean / max over units, per target)."""
    lines = [f"{'method':<46}{'group':<7}{'min':>7}{'mean':>7}{'max':>7}{'width':>9}"]
    keyed: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in rows:
        if r.get("nominal_coverage") == 0.9 and "group" in r and is_target(r):
            keyed.setdefault((r["method"], r["group"]), []).append(r)
    for (method, group), rs in keyed.items():
        c = [r["coverage"] for r in rs]
        lines.append(f"{method:<46}{group:<7}{min(c):>7.3f}{np.mean(c):>7.3f}{max(c):>7.3f}"
                     f"{np.mean([r['interval_width'] for r in rs]):>11.4g}")
    return "\n".join(lines)


def adapted_rows(ctx: Context, arrays: FleetArrays, a: AdaptedOptions, levels: list[float],
                 seed: int, beta: float = 0.5, bootstrap: int = 0) -> list[dict[str, Any]]:
    """Intervals of the adapted shared model on held-out units (variants in
    `adapted_variants`), split conformal two ways: `val_units` pools the validation units'
    scores (each through its own folded model, on its own test rows); `budget` uses the
    held-out unit's own stream, the `calib_rows` rows after the `budget` rows that fitted its
    adapter. Test rows are the held-out patches (`test: patches`) or every row of the unit
    that the adapter and the conformal set did not read (`unseen`: about 70 patch cells, so
    one unit's coverage is pinned to about 0.01-0.03, `coverage_sd`)."""
    co = CrossOptions(calibration_protocol=a.calibration_protocol, priors=[a.prior], adapters=[a.kind],
                      sweep_adapter=a.kind, calibration_interleave=a.calibration_interleave)
    sd = cross_prepare(ctx, arrays, co, seed)
    units = [*sd.split.val, *sd.split.test]
    streams = [sd.evals[u].stream for u in units]
    cal = [st.rows[a.budget:a.budget + a.calib_rows] for st in streams]
    if a.test == "patches":
        test = [sd.evals[u].test_rows for u in units]
    else:
        test = [unseen_rows(arrays, st, a.budget + a.calib_rows, a.max_test_rows,
                            stream_seed(UNSEEN_ROWS, seed, m))
                for m, st in enumerate(streams)]
    some = [c if len(c) else t[:1] for c, t in zip(cal, test, strict=True)]  # empty: no budget variant
    variants = adapted_variants(ctx, arrays, sd, co, a, streams, test, some, seed, beta)
    y = arrays.targets.astype(np.float64)
    n_val = len(sd.split.val)
    rows = []
    for name, v in variants.items():
        sig_t, sig_c, mu_t, mu_c = v.sigma_test, v.sigma_cal, v.mean_test, v.mean_cal
        pooled = np.concatenate([cp.scores_of(mu_t[m], y[test[m]], sig_t[m]) for m in range(n_val)])
        for m in range(n_val, len(units)):
            patches = arrays.patch[test[m]]  # cells, as in the per-unit patch bootstrap
            base = {"unit": units[m], "seed": seed, "calib_samples": a.budget, "test": a.test,
                    "n_train_units": len(sd.split.train), "test_rows": len(test[m]),
                    "test_patches": len(np.unique(patches))}
            boot_args = (patches, bootstrap, stream_seed(BOOTSTRAP, seed, m))
            if v.gaussian:  # the uncalibrated Gaussian beside it
                rows += method_rows(v.gaussian, MethodPreds(
                    mu_t[m], sig_t[m], mu_c[m], sig_c[m], "gaussian"), y[test[m]], y[:0],
                    {**base, "members": a.members if "+ensemble" in name else 1}, levels, *boot_args,
                    layout=arrays.layout)
            p = MethodPreds(mu_t[m], sig_t[m], mu_c[m], sig_c[m], "conformal")
            rows += method_rows(f"{name}:val_units", replace(p, pooled_scores=pooled), y[test[m]], y[:0],
                                {**base, "conformal_rows": len(pooled)}, levels, *boot_args,
                                layout=arrays.layout)
            if len(cal[m]):
                rows += method_rows(f"{name}:budget", p, y[test[m]], y[cal[m]],
                                    {**base, "conformal_rows": len(cal[m])}, levels, *boot_args,
                                    layout=arrays.layout)
    return rows


@dataclass
class AdaptedMember:
    """One shared model trained from a seed, its adapters fitted on every unit's budget and
    folded: the unit input statistics, its predictions per unit on the test rows and on the
    conformal rows ((n, d), or (n, 2d) for a heteroscedastic model: means, then log sigma^2),
    and the folded models."""

    shared: SharedFit
    stats: Scaler
    pred_test: list[np.ndarray]
    pred_cal: list[np.ndarray]
    folded: BatchedMLP


@dataclass
class Variant:
    """One conformal variant of the adapted model, per unit on test and on conformal rows: its
    scales (None: absolute residual) and means, and the uncalibrated Gaussian method beside it."""

    sigma_test: list[np.ndarray | None]
    sigma_cal: list[np.ndarray | None]
    mean_test: list[np.ndarray]
    mean_cal: list[np.ndarray]
    gaussian: str | None = None


def adapted_variants(ctx: Context, arrays: FleetArrays, sd, co: CrossOptions, a: AdaptedOptions,
                     streams: list, test: list[np.ndarray], cal: list[np.ndarray], seed: int,
                     beta: float) -> dict[str, Variant]:
    """The conformal variants of the adapted model, by method name.

    `+conformal`: absolute residual. `+scale`: a scale network's sigma; `+fscale`:
    a + b |F_hat| (both `anytip.uncertainty.shared_scale`, fitted on the training units'
    validation rows). `+ensemble` (members >= 2): shared models from other seeds, each with
    its own adapters, folded; their mean, scaled by their spread. `+hetero`: a shared model
    with heteroscedastic heads, its adapters fitted by beta-NLL too, folded and saved with
    its scale outputs; scaled by its own sigma."""
    members = [adapted_member(ctx, arrays, sd, co, a, streams, test, cal,
                              stream_seed(ENSEMBLE_MEMBER, seed, k) if k else seed)
               for k in range(a.members)]
    first = members[0]
    shared, stats, pred_t, pred_c = first.shared, first.stats, first.pred_test, first.pred_cal
    n = len(streams)
    variants = {f"adapted:{a.kind}+conformal": Variant([None] * n, [None] * n, pred_t, pred_c)}
    if a.scale_epochs:
        net = fit_scale_network(*shared_residuals(shared, sd.train), ctx.spec.model, a.scale_epochs,
                                seed=seed)

        def sigma(rows: list[np.ndarray]) -> list[np.ndarray]:
            return [predict_scale(net, stats.slice(m), shared.out_scaler, arrays.pressure[r])
                    for m, r in enumerate(rows)]

        variants[f"adapted:{a.kind}+scale+conformal"] = Variant(sigma(test), sigma(cal), pred_t, pred_c)
    if has_patch_grid(arrays.layout):  # a + b |F_hat| needs the fingertip's force in the first columns
        coef = fit_force_scale(shared, sd.train)
        variants[f"adapted:{a.kind}+fscale+conformal"] = Variant(
            [force_scale(p, coef) for p in pred_t], [force_scale(p, coef) for p in pred_c], pred_t, pred_c)
    if a.members > 1:
        (ens_t, spread_t) = ensemble_of([m.pred_test for m in members])
        (ens_c, spread_c) = ensemble_of([m.pred_cal for m in members])
        variants[f"adapted:{a.kind}+ensemble+conformal"] = Variant(spread_t, spread_c, ens_t, ens_c,
                                                                   f"adapted:{a.kind}+ensemble")
    if a.hetero:
        het = adapted_member(ctx, arrays, sd, co, a, streams, test, cal, seed, hetero_beta=beta)
        save_hetero(ctx, het, list(sd.split.test), seed, beta)
        (mu_t, sig_t), (mu_c, sig_c) = gaussian_heads(het.pred_test), gaussian_heads(het.pred_cal)
        variants[f"adapted:{a.kind}+hetero+conformal"] = Variant(sig_t, sig_c, mu_t, mu_c,
                                                                 f"adapted:{a.kind}+hetero")
    return variants


def adapted_member(ctx: Context, arrays: FleetArrays, sd, co: CrossOptions, a: AdaptedOptions,
                   streams: list, test: list[np.ndarray], cal: list[np.ndarray], seed: int,
                   hetero_beta: float | None = None) -> AdaptedMember:
    """One shared model trained from `seed`, its adapters fitted on every unit's budget and
    folded. With `hetero_beta` the predictions are (n, 2d): the physical means, then log
    sigma^2 (the saved model's outputs, `output_scaler_2d`)."""
    recipe = ctx.spec.training.model_copy(update={"epochs": a.epochs})
    shared = train_shared(sd.train, sd.train_stats, ctx.spec.model, a.kind, recipe, seed, ctx.device,
                          adapter_decay=co.adapter_decay, hetero_beta=hetero_beta)
    plans = [stream_plan(s, a.budget) for s in streams]
    folded, stats = calibrate_many(shared, arrays, [s.rows for s in streams], plans, [a.prior] * len(plans),
                                   AdapterRecipe(co.adapter_steps, co.adapter_lr), seed)
    out = shared.out_scaler if hetero_beta is None else output_scaler_2d(shared.out_scaler)
    return AdaptedMember(shared, stats, predict_rows(folded, stats, out, arrays, test),
                         predict_rows(folded, stats, out, arrays, cal), folded)


def unseen_rows(arrays: FleetArrays, stream, seen: int, max_rows: int, seed: int) -> np.ndarray:
    """Every row of the stream's unit except the first `seen` rows of its stream (what the
    adapter and the conformal set read), at most `max_rows` of them drawn at random: all its
    patches stay represented, each in proportion to its rows."""
    mine = np.flatnonzero(arrays.unit == arrays.units.index(stream.unit))
    rest = np.setdiff1d(mine, stream.first(seen))
    return capped(rest, max_rows, np.random.default_rng(seed))


def gaussian_heads(preds: list[np.ndarray]) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Saved heteroscedastic outputs [(n, 2d), ...] -> means [(n, d)] and sigmas [(n, d)]."""
    d = preds[0].shape[1] // 2
    return [p[:, :d] for p in preds], [np.exp(0.5 * p[:, d:]) for p in preds]


def save_hetero(ctx: Context, member: AdaptedMember, units: list[str], seed: int, beta: float) -> None:
    """Save the held-out units' folded heteroscedastic models (the last len(units) of the
    member's models), scale outputs included, ready for `anytip export`."""
    shared, stats, folded = member.shared, member.stats, member.folded
    keep = list(range(folded.n_models - len(units), folded.n_models))
    save_models(ctx.run_dir / "models" / f"adapted_hetero_seed{seed}",
                BatchedMLP.from_plain([folded.to_plain(m) for m in keep], folded.config),
                stats.take(keep), output_scaler_2d(shared.out_scaler).take([0] * len(units)),
                {"unit_ids": units, **hetero_meta(shared.out_scaler.mean.shape[-1], beta),
                 "adapter": shared.model.kind, "seed": seed})


def ensemble_of(preds: list[list[np.ndarray]]) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Members' predictions [K][units] (n, 5) -> per unit the mean and the members' spread (std,
    floored at 1e-9 so that normalised scores stay finite)."""
    stacked = [np.stack(unit) for unit in zip(*preds, strict=True)]
    return [p.mean(0) for p in stacked], [np.maximum(p.std(0), 1e-9) for p in stacked]
