"""The cross-sensor report: accuracy on held-out units against calibration budget, as ratios
to their per-unit models, and against the number of training units."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from scipy import stats

from anytip.errors import AnytipError
from anytip.report.figures import plain_ratio_axis, save_figure, subplots
from anytip.report.markdown import table
from anytip.report.metric import FINGERTIP_METRICS, Metric
from anytip.report.writer import Report

if TYPE_CHECKING:
    from pathlib import Path

    from matplotlib.figure import Figure


METRICS = FINGERTIP_METRICS


def full_set_rows(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Rows of the full training set (the unit-count sweep's smaller sets left out)."""
    full = max(r["n_train_units"] for r in rows)
    return [r for r in rows if r["n_train_units"] == full]


def is_reference(method: str) -> bool:
    """Per-unit models on the unit's full calibration: the reference `per_unit` and the same
    recipe in other shapes (`per_unit:8-48-48-48-5`, `options.reference_shapes`)."""
    return method == "per_unit" or method.startswith("per_unit:")


def budget_of(r: dict[str, Any]) -> float:
    """A row's budget: robot seconds where the spec budgets in seconds, else labeled samples;
    -1 (the full calibration) for per-unit models."""
    if is_reference(r["method"]):
        return -1.0
    return r["budget_s"] if "budget_s" in r else r["calib_samples"]


def in_seconds(rows: list[dict[str, Any]]) -> bool:
    return any("budget_s" in r for r in rows)


def ratios(rows: list[dict[str, Any]], key: str) -> dict[tuple[str, int], list[float]]:
    """(method, budget) -> per (unit, seed) ratios of `key` to that unit's per_unit value."""
    ref = {(r["unit"], r["seed"]): r[key] for r in rows if r["method"] == "per_unit"}
    out: dict[tuple[str, int], list[float]] = defaultdict(list)
    for r in rows:
        if r["method"] != "per_unit" and (r["unit"], r["seed"]) in ref:
            out[(r["method"], budget_of(r))].append(r[key] / ref[(r["unit"], r["seed"])])
    return out


def unit_ratios(rows: list[dict[str, Any]], key: str) -> dict[tuple[str, float], dict[str, float]]:
    """(method, budget) -> {held-out unit: ratio}: the unit's `key` averaged over its seeds, over
    its per_unit reference's `key` averaged over the same seeds. A row without its reference
    (same unit and seed) is an error: a ratio is never taken against another unit's model."""
    ref = {(r["unit"], r["seed"]): r[key] for r in rows if r["method"] == "per_unit"}
    acc: dict[tuple[str, float], dict[str, list[tuple[float, float]]]]
    acc = defaultdict(lambda: defaultdict(list))
    for r in rows:
        if r["method"] == "per_unit":
            continue
        if (r["unit"], r["seed"]) not in ref:
            raise AnytipError(f"row {r['method']} of unit {r['unit']}, seed {r['seed']} has no per_unit "
                              "reference in the run; a held-out unit is scored against its own model only")
        acc[(r["method"], budget_of(r))][r["unit"]].append((r[key], ref[(r["unit"], r["seed"])]))
    return {mb: {u: float(np.mean([v for v, _ in pairs]) / np.mean([f for _, f in pairs]))
                 for u, pairs in by_unit.items()} for mb, by_unit in acc.items()}


def mean_interval(values: list[float], level: float = 0.95, n_boot: int = 4000) -> tuple[float, float, float]:
    """(mean, lower, upper): the mean over units and its percentile bootstrap interval over units
    (a fixed draw, so a report reproduces); NaN bounds for fewer than two units."""
    v = np.asarray(values, float)
    if len(v) < 2:
        return float(v.mean()), float("nan"), float("nan")
    boot = v[np.random.default_rng(0).integers(0, len(v), (n_boot, len(v)))].mean(1)
    lo, hi = np.percentile(boot, [50 * (1 - level), 50 * (1 + level)])
    return float(v.mean()), float(lo), float(hi)


def paired_interval(ratios: list[float]) -> tuple[float, float, float]:
    """Per-unit ratios of one method or model over another on the same units: their geometric mean
    and its 95% bootstrap interval over units, (mean, lower, upper)."""
    m, lo, hi = (float(np.exp(v)) for v in mean_interval([float(np.log(r)) for r in ratios]))
    return m, lo, hi


def paired_text(ratios: list[float]) -> str:
    """`paired_interval` as text: `mean [lower, upper]`."""
    m, lo, hi = paired_interval(ratios)
    return f"{m:.3f} [{lo:.3f}, {hi:.3f}]"


def summary(rows: list[dict[str, Any]], metrics: Sequence[Metric] = METRICS) -> list[dict[str, Any]]:
    """One line per (method, budget): for each metric (by its name, e.g. `force`) the mean over
    units and seeds and ratios to per_unit: the mean of (unit, seed) ratios (`force_ratio`), and
    per distinct unit (seeds averaged first, `force_unit`: mean, lower, upper) with a 95%
    bootstrap interval over units."""
    pair = {m.name: ratios(rows, m.key) for m in metrics}
    per_unit = {m.name: unit_ratios(rows, m.key) for m in metrics}
    groups: dict[tuple[str, int], list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        groups[(r["method"], budget_of(r))].append(r)
    out = []
    for (method, budget), rs in sorted(groups.items(), key=lambda kv: (kv[0][1], kv[0][0])):
        secs = [r["calib_seconds"] for r in rs if r.get("calib_seconds") is not None]
        line = {"method": method, "budget": budget, "n": len(rs),
                "seconds": float(np.mean(secs)) if secs else None, "units": len({r["unit"] for r in rs})}
        for m in metrics:
            line[m.name] = float(np.mean([r[m.key] for r in rs]))
            r_pair = pair[m.name].get((method, budget))
            line[f"{m.name}_ratio"] = float(np.mean(r_pair)) if r_pair else 1.0
            values = list(per_unit[m.name].get((method, budget), {}).values())
            line[f"{m.name}_unit"] = mean_interval(values) if values else (1.0, float("nan"), float("nan"))
        out.append(line)
    return out


def plan_of_method(method: str) -> str | None:
    """The plan strategy a method's rows used (`adapted:kind@spread` -> spread), or None."""
    return method.split("@", 1)[1] if "@" in method else None


Key = tuple[float, str | None]  # (budget, plan strategy or data family)


def _competitors(val_loss: dict[str, dict[str, dict[str, float]]],
                 key_of: Callable[[float, str], Key]) -> dict[Key, dict[str, dict[str, float]]]:
    """key -> {method: {seed: validation-unit loss}}: the methods that compete for each choice,
    `key_of(budget, method)` naming the choice."""
    acc: dict[Key, dict[str, dict[str, float]]] = defaultdict(dict)
    for seed, per_method in val_loss.items():
        for method, per_budget in per_method.items():
            for budget, loss in per_budget.items():
                acc[key_of(float(budget), method)].setdefault(method, {})[seed] = float(loss)
    return acc


def _by_strategy(budget: float, method: str) -> Key:
    """A choice per (budget, plan strategy); label-free methods (budget 0) compete under None."""
    return budget, None if budget == 0 else plan_of_method(method)


def chosen_methods(val_loss: dict[str, dict[str, dict[str, float]]]) -> dict[Key, str]:
    """Per (budget, plan strategy), the method with the lowest validation-unit loss averaged
    over seeds: val_loss is {seed: {method: {budget: loss}}} as the pipeline records it.
    Held-out units never take part in this choice."""
    return {key: min(m, key=lambda k: np.mean(list(m[k].values())))
            for key, m in _competitors(val_loss, _by_strategy).items()}


class ChoiceMargin(NamedTuple):
    """How firmly the validation units chose one method over the runner-up: `margin` is the
    runner-up's loss over the chosen method's, each averaged over seeds, less 1; `per_seed` the same
    per seed holding both; (lower, upper) the 95% t-interval of the mean log ratio, as a margin, over
    the `n` pairs it was taken over (`over`: each validation unit's losses where the run recorded
    them, else each seed's mean; NaN with fewer than three)."""

    method: str
    runner_up: str
    margin: float
    per_seed: list[float]
    lower: float
    upper: float
    n: int = 0
    over: str = "seeds"

    @property
    def verdict(self) -> str:
        """`resolved` where the interval lies above 0, `not resolved` where it holds 0, else why
        there is no interval."""
        if np.isnan(self.lower):
            return f"{self.n} {self.over}: no interval"
        return "resolved" if self.lower > 0 else "not resolved"


def _t_interval(logs: np.ndarray) -> tuple[float, float]:
    """The 95% t-interval of the mean of log ratios, as margins (NaN with fewer than three)."""
    if len(logs) < 3:
        return float("nan"), float("nan")
    half = stats.t.ppf(0.975, len(logs) - 1) * logs.std(ddof=1) / np.sqrt(len(logs))
    return float(np.expm1(logs.mean() - half)), float(np.expm1(logs.mean() + half))


def _unit_logs(val_units: dict[str, dict[str, dict[str, dict[str, float]]]], best: str, runner_up: str,
               budget: float) -> np.ndarray:
    """log(runner-up / best) of each validation unit both methods' records hold at `budget`, averaged
    over the seeds that hold it: a unit validating in several seeds (or start-network draws) is one
    pair, as the held-out figures average a unit's seeds first."""
    logs: dict[str, list[float]] = defaultdict(list)
    for per_method in val_units.values():
        a, b = ({float(k): v for k, v in per_method.get(m, {}).items()}.get(budget, {})
                for m in (best, runner_up))
        for u in a:
            if u in b:
                logs[u].append(float(np.log(b[u] / a[u])))
    return np.array([np.mean(v) for v in logs.values()])


def choice_margins(val_loss: dict[str, dict[str, dict[str, float]]],
                   family: Callable[[str], str] | None = None,
                   val_units: dict[str, dict[str, dict[str, dict[str, float]]]] | None = None
                   ) -> dict[Key, ChoiceMargin]:
    """Per (budget, family) with at least two methods, the best method's margin over the runner-up
    on the validation units (`ChoiceMargin`), every plan strategy competing; `family(method)` names
    the data a method uses (labels alone, ordinary use besides), so that only methods given the same
    data compete (None: all of them). `val_units` ({seed: {method: {budget: {unit: loss}}}}, as runs
    record `val_loss_units`) pairs the two methods unit by unit; without it each seed's mean is one
    pair (a seed's validation units, a fold's in folds, are one draw of units)."""
    out = {}
    named = family or (lambda method: "")
    for key, methods in _competitors(val_loss, lambda b, m: (b, named(m))).items():
        if len(methods) < 2:
            continue
        first, second = sorted(methods, key=lambda k: np.mean(list(methods[k].values())))[:2]
        a, b = methods[first], methods[second]
        per_seed = np.log([b[s] / a[s] for s in a if s in b])
        logs, over = per_seed, "seeds"
        by_unit = _unit_logs(val_units or {}, first, second, key[0])
        if len(by_unit):
            logs, over = by_unit, "validation units"
        margin = float(np.mean(list(b.values())) / np.mean(list(a.values())) - 1)
        out[key] = ChoiceMargin(first, second, margin, [float(v) for v in np.expm1(per_seed)],
                                *_t_interval(logs), len(logs), over)
    return out


def margin_rows(margins: dict[Key, ChoiceMargin]) -> list[list[str]]:
    """The report's table of `choice_margins`, in budget order."""
    return [[f"{budget:g}", name or "", f"`{m.method}`", f"`{m.runner_up}`",
             f"{100 * m.margin:+.1f}%", " ".join(f"{100 * v:+.1f}" for v in m.per_seed),
             "" if np.isnan(m.lower) else f"[{100 * m.lower:+.1f}, {100 * m.upper:+.1f}]%", f"{m.n} {m.over}",
             m.verdict]
            for (budget, name), m in sorted(margins.items(), key=lambda kv: (kv[0][0], str(kv[0][1])))]


def targets(lines: list[dict[str, Any]], chosen: dict[tuple[float, str | None], str],
            seconds: bool = False, metrics: Sequence[Metric] = METRICS) -> list[list[Any]]:
    """The benchmark's targets, each at the largest budget that meets its condition (the
    smallest for `>=` conditions) and for each plan strategy, with the method chosen there on
    validation units (`chosen_methods`): its held-out ratio per unit, mean [95% interval over
    units]."""
    checks = [
        ("zero-shot (0 labeled samples)", "<= 2.0x", 2.0, None, lambda b: b == 0),
        ("<= 1000 labeled samples", "<= 1.10x, upper <= 1.25x", 1.10, 1.25, lambda b: 0 < b <= 1000),
        ("5000 labeled samples", "< 1.0x", 1.0, None, lambda b: b >= 5000),
    ]
    if seconds:
        checks = [
            ("zero-shot (no labels)", "<= 2.0x", 2.0, None, lambda b: b == 0),
            ("<= 120 s of robot time", "<= 1.10x, upper <= 1.25x", 1.10, 1.25, lambda b: 0 < b <= 120),
            ("600 s of robot time", "< 1.0x", 1.0, None, lambda b: b == 600),
        ]
    by_key = {(s["method"], s["budget"]): s for s in lines}
    strategies = sorted({st for _, st in chosen if st is not None}) or [None]
    out = []
    for name, goal, limit, upper, cond in checks:
        for strategy in ([None] if limit == 2.0 else strategies):
            keys = [(b, st) for b, st in chosen
                    if cond(b) and st == strategy and (chosen[(b, st)], b) in by_key]
            label = name if strategy is None else f"{name}, `{strategy}`"
            if not keys:
                out.append([label, goal, "n/a (no validation choice)", *([""] * len(metrics)), ""])
                continue
            b = (min if limit == 1.0 else max)(k[0] for k in keys)
            s = by_key[(chosen[(b, strategy)], b)]
            worst = max(s[f"{m.name}_unit"][0] for m in metrics)
            met = worst < 1.0 if limit == 1.0 else worst <= limit
            if upper is not None:
                met = met and max(s[f"{m.name}_unit"][2] for m in metrics) <= upper
            out.append([label, goal, f"`{s['method']}` @ {b:g}",
                        *(ratio_text(s[f"{m.name}_unit"]) for m in metrics), "met" if met else "**not met**"])
    return out


def rmse_text(v: float) -> str:
    """An RMSE in its unit: three decimals, or three significant digits below 0.01 (metres)."""
    return f"{v:.3f}" if abs(v) >= 0.01 else f"{v:.3g}"


def ratio_text(m: tuple[float, float, float]) -> str:
    """A unit-level ratio as `mean [lower, upper]`."""
    return f"{m[0]:.2f}x" if np.isnan(m[1]) else f"{m[0]:.2f}x [{m[1]:.2f}, {m[2]:.2f}]"


def budget_figure(rows: list[dict[str, Any]], path: Path, metrics: Sequence[Metric] = METRICS) -> Path:
    """Each metric's RMSE against the budget, per method: median over units and seeds, band
    from the 10th to the 90th percentile; per_unit as a horizontal band."""
    fig, axes = subplots(1, len(metrics), figsize=(6 * len(metrics), 4.5), squeeze=False)
    axes = axes[0]
    methods = sorted({r["method"] for r in rows if not is_reference(r["method"])})
    budgets = sorted({budget_of(r) for r in rows if not is_reference(r["method"])})
    pos = {b: (i if b > 0 else 0) for i, b in enumerate(budgets)}
    fleet = [r for r in rows if not is_reference(r["method"])]
    secs = {b: np.mean([r["calib_seconds"] for r in fleet if budget_of(r) == b
                        and r.get("calib_seconds") is not None] or [0.0]) for b in budgets}
    for ax, (key, _, label) in zip(axes, metrics, strict=True):
        ref = [r[key] for r in rows if r["method"] == "per_unit"]
        if ref:
            lo, med, hi = np.percentile(ref, [10, 50, 90])
            ax.axhspan(lo, hi, color="k", alpha=0.08)
            ax.axhline(med, color="k", ls="--", lw=1.2, label="per_unit (full calibration)")
        for m in methods:
            pts = sorted({budget_of(r) for r in rows if r["method"] == m})
            vals = [[r[key] for r in rows if r["method"] == m and budget_of(r) == b] for b in pts]
            x = [pos[b] for b in pts]
            p = np.array([np.percentile(v, [10, 50, 90]) for v in vals])
            ax.plot(x, p[:, 1], marker="o", label=m)
            ax.fill_between(x, p[:, 0], p[:, 2], alpha=0.12)
        if in_seconds(rows):
            ax.set_xticks([pos[b] for b in budgets], [f"{b:g}" for b in budgets])
            ax.set(xlabel="calibration budget [robot-seconds]", ylabel=label, yscale="log")
        else:
            ax.set_xticks([pos[b] for b in budgets],
                          [f"{b}\n{secs[b]:.1f} s" if b > 0 else "0" for b in budgets])
            ax.set(xlabel="labeled calibration samples (robot-seconds)", ylabel=label, yscale="log")
        ax.grid(alpha=0.3, which="both")
    axes[0].legend(fontsize=7)
    fig.suptitle("held-out units: error against calibration budget (median, 10-90% band)")
    return save_figure(fig, path)


def ratio_figure(lines: list[dict[str, Any]], path: Path, seconds: bool,
                 metrics: Sequence[Metric] = METRICS) -> Path:
    """Each metric's ratio to per_unit against the budget, per method (`summary` lines): the
    mean over distinct held-out units with its 95% bootstrap interval; 1.0 and 1.1 marked."""
    fleet = [ln for ln in lines if not is_reference(ln["method"])]
    series = {method: sorted((ln for ln in fleet if ln["method"] == method), key=lambda ln: ln["budget"])
              for method in sorted({ln["method"] for ln in fleet})}
    return save_figure(_ratio_plot(series, seconds, metrics), path)


def _ratio_plot(series: dict[str, list[dict[str, Any]]], seconds: bool, metrics: Sequence[Metric]) -> Figure:
    """One panel per metric: its ratio to per_unit against the budget, one errorbar line per series
    (`summary` lines in budget order: mean over distinct held-out units, 95% interval), the series
    side by side within a budget; 1.0 and 1.1 marked."""
    fig, axes = subplots(1, len(metrics), figsize=(6 * len(metrics), 4.5), squeeze=False)
    budgets = sorted({ln["budget"] for lines in series.values() for ln in lines})
    pos = {b: i for i, b in enumerate(budgets)}
    unit = "robot-seconds" if seconds else "labeled samples"
    for ax, m in zip(axes[0], metrics, strict=True):
        for k, (label, lines) in enumerate(series.items()):
            mean, lo, hi = (np.array([ln[f"{m.name}_unit"][i] for ln in lines]) for i in range(3))
            shift = 0.6 * (k / max(len(series) - 1, 1) - 0.5)  # side by side within a budget
            x = np.array([pos[ln["budget"]] for ln in lines]) + shift
            ax.errorbar(x, mean, yerr=[mean - lo, hi - mean], marker="os^Dv"[k // 10 % 5], capsize=3,
                        label=label)
        ax.axhline(1.0, color="k", ls="--", lw=1.2, label="per_unit")
        ax.axhline(1.1, color="k", ls=":", lw=1, label="1.1x")
        ax.set_xticks(list(pos.values()), [f"{b:g}" if b >= 0 else "full" for b in budgets])
        ax.set(xlabel=f"calibration budget [{unit}]", ylabel=f"{m.name} RMSE / per_unit")
        plain_ratio_axis(ax)
        ax.grid(alpha=0.3, which="both")
    axes[0][0].legend(fontsize=7)
    fig.suptitle("held-out units: ratio to their own per-unit models (mean over units, 95% interval)")
    return fig


def unit_count_figure(rows: list[dict[str, Any]], method: str, path: Path,
                      metric: Metric = METRICS[0]) -> Path | None:
    """The first metric's RMSE ratio to per_unit against the number of training units, one line
    per budget."""
    ref = {(r["unit"], r["seed"]): r[metric.key] for r in rows if r["method"] == "per_unit"}
    sel = [r for r in rows if r["method"].split("@")[0] == method and (r["unit"], r["seed"]) in ref]
    counts = sorted({r["n_train_units"] for r in sel})
    seeds = {r["seed"] for r in rows if r["n_train_units"] < max(counts, default=0)}
    if len(counts) < 2:
        return None
    fig, ax = subplots(figsize=(6, 4))
    unit = "robot-s" if in_seconds(sel) else "labeled samples"
    for b in sorted({budget_of(r) for r in sel if r["n_train_units"] < max(counts)}):
        ys = []
        for k in counts:
            v = [r[metric.key] / ref[(r["unit"], r["seed"])] for r in sel
                 if r["n_train_units"] == k and budget_of(r) == b and r["seed"] in seeds]
            ys.append(np.percentile(v, [10, 50, 90]) if v else [np.nan] * 3)
        ys = np.array(ys)
        ax.plot(counts, ys[:, 1], marker="o", label=f"{b:g} {unit}")
        ax.fill_between(counts, ys[:, 0], ys[:, 2], alpha=0.15)
    ax.axhline(1.0, color="k", ls="--", lw=1, label="per_unit")
    ax.set(xscale="log", xlabel="training units", ylabel=f"{metric.name} RMSE / per_unit",
           title=f"{method}: how many units to calibrate fully")
    ax.minorticks_off()
    ax.set_xticks(counts, [str(c) for c in counts])
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save_figure(fig, path)


def write_report(ctx: Any, rows: list[dict[str, Any]], opts: Any,
                 metrics: Sequence[Metric] = METRICS, family: Callable[[str], str] | None = None) -> Path:
    """The report of a cross-sensor run; `metrics` are the sensor model's targets, `family(method)` the
    data a method uses (`choice_margins`)."""
    main = full_set_rows(rows)
    lines = summary(main, metrics)
    budget_figure(main, ctx.run_dir / "rmse_vs_budget.png", metrics)
    units_fig = unit_count_figure(rows, f"adapted:{opts.sweep_adapter}",
                                  ctx.run_dir / "rmse_vs_train_units.png", metrics[0])
    seconds = in_seconds(main)
    ratio_figure(lines, ctx.run_dir / "ratio_vs_budget.png", seconds, metrics)
    body = [[s["method"], "full" if s["budget"] < 0 else f"{s['budget']:g}",
             "" if s["seconds"] is None else f"{s['seconds']:.1f}",
             *(v for m in metrics for v in (rmse_text(s[m.name]), ratio_text(s[f"{m.name}_unit"]))),
             s["units"], s["n"]]
            for s in lines]
    ratio_heads = [f"{m.name} ratio" for m in metrics]
    held = "patches" if main[0].get("split", "patches") == "patches" else "blocks of rows"
    all_heads = [h for m in metrics for h in (m.label, f"{m.name} / per_unit [95% CI]")]
    val_loss = {k: v.get("val_loss", {}) for k, v in ctx.provenance.get("cross_sensor", {}).items()}
    val_units = {k: v.get("val_loss_units", {}) for k, v in ctx.provenance.get("cross_sensor", {}).items()}
    chosen = chosen_methods(val_loss)
    seeds = sorted({r["seed"] for r in rows})
    cs = ctx.provenance.get("cross_sensor", {})
    first = next(iter(cs.values()), {}).get("units", {})
    intervals = interval_section(rows, output_units(ctx.provenance))
    return Report(ctx.run_dir).add(f"""# {ctx.spec.name}: one model for many units

{ctx.spec.description.strip()}

{len(ctx.provenance.get('units', []))} units of `{ctx.provenance.get('sensor_model')}`; per seed
{len(first.get('train', []))} training, {len(first.get('val', []))} validation and
{len(first.get('test', []))} held-out units (seeds {seeds}).{_extra_text(ctx.provenance)}
{pooled_section(ctx.provenance)}
Every method is scored on the same held-out {held}
({ctx.spec.splits.patch_test_fraction:.0%} of each held-out unit's {held}) that no method saw in
any run. {_budget_text(opts, seconds)}
{_shape_text(ctx, opts)} The adapter prior is chosen per budget on the
validation units. Label-free rows (budget 0) use the unit's unlabeled stream for input statistics.

## Targets (ratios to the held-out units' own per-unit models)

The method of each target is the one with the lowest validation-unit loss at that budget
(mean over seeds); held-out units never choose it. Ratios are per distinct held-out unit (its
RMSE over its own per-unit model's, seeds averaged first): mean over units [95% bootstrap
interval over units].

{table(['target', 'goal', 'method (chosen on validation units)', *ratio_heads, ''],
       targets(lines, chosen, seconds, metrics))}
{_decided_text(opts)}{margin_section(val_loss, family, val_units)}
## All methods (RMSE: mean over held-out units and seeds; ratios per distinct unit)

{table(['method', 'budget [robot-s]' if seconds else 'labeled samples', 'robot-s', *all_heads,
        'units', 'rows'], body)}

![error against calibration budget](rmse_vs_budget.png)

![ratio to the per-unit models against calibration budget](ratio_vs_budget.png)
{own_check_section(cs)}{intervals}""" + ("" if units_fig is None else """
## How many units to calibrate fully

![error against training units](rmse_vs_train_units.png)
""")).write()


def _decided_text(opts: Any) -> str:
    """A paragraph naming the press selection the spec decided for response transfer beforehand
    (`options.response.plan_strategy`); empty where the run's validation units choose."""
    decided = opts.response.plan_strategy if opts.response is not None else None
    if decided is None:
        return ""
    return f"""
Response transfer's press selection was decided before this run, by its spec, on more validation
units than a run holds (`options.response.plan_strategy`): `{decided}`. Its rows above are the
figures for a unit calibrated from this run: `anytip calibrate` takes that selection whatever this
run's validation units chose below.
"""


def margin_section(val_loss: dict[str, dict[str, dict[str, float]]], family: Callable[[str], str] | None,
                   val_units: dict[str, dict[str, dict[str, dict[str, float]]]]) -> str:
    """How firmly the validation units chose among the methods given the same data
    (`choice_margins`); empty where no budget had two."""
    margins = choice_margins(val_loss, family, val_units)
    if not margins:
        return ""
    return f"""
### How firmly the validation units chose

At each budget, among the methods given the same data (every plan strategy competing): the best
method on the validation units, the runner-up, the runner-up's loss over the best's less 1 (mean
over seeds, then per seed), and the 95% t-interval of that margin over the validation units paired
one by one (where the run recorded each unit's loss), else over seeds (three or more). Where the
interval holds 0 the validation units do not resolve the choice, and the runner-up may do as well or
better on held-out units (research log entry 96).

{table(['budget', 'data', 'best', 'runner-up', 'margin', 'per seed (%)', '95% interval', 'over', ''],
       margin_rows(margins))}
"""


def chosen_lines(rows: list[dict[str, Any]], val_loss: dict[str, dict[str, dict[str, float]]],
                 metrics: Sequence[Metric] = METRICS) -> list[dict[str, Any]]:
    """The `summary` line of each (budget, plan strategy)'s method as the run's validation units
    chose it (`chosen_methods`; full training set only), with its `strategy`, in budget order."""
    by_key = {(s["method"], s["budget"]): s for s in summary(full_set_rows(rows), metrics)}
    chosen = chosen_methods(val_loss)
    return [{**by_key[(method, budget)], "strategy": strategy}
            for (budget, strategy), method in sorted(chosen.items(), key=lambda kv: (kv[0][0], str(kv[0][1])))
            if (method, budget) in by_key]


def named_lines(rows: list[dict[str, Any]], method: str, metrics: Sequence[Metric] = METRICS,
                source: Any = "the run") -> list[dict[str, Any]]:
    """The `summary` lines of `method` at each budget (full training set only), in budget order,
    with its plan `strategy`; a method the rows do not hold is refused, naming the ones they do."""
    lines = [ln for ln in summary(full_set_rows(rows), metrics) if ln["method"] == method]
    if not lines:
        held = sorted({r["method"] for r in rows if not is_reference(r["method"])})
        raise AnytipError(f"{source}: no rows of method {method!r}; it holds {', '.join(held)}")
    return [{**ln, "strategy": plan_of_method(method)} for ln in lines]


def comparison_report(report: Report, groups: dict[str, list[dict[str, Any]]], seconds: bool,
                      metrics: Sequence[Metric] = METRICS) -> Report:
    """Several runs side by side (`anytip compare`): per entry (its label) and budget, a method (the
    entry's validation choice, `chosen_lines`, or one named, `named_lines`) and its ratios to the
    held-out units' own per-unit models, as a table and a figure."""
    unit = "robot-s" if seconds else "labeled samples"
    body = [[label, f"{ln['budget']:g}", f"`{ln['method']}`",
             "" if ln["seconds"] is None else f"{ln['seconds']:.1f}",
             *(ratio_text(ln[f"{m.name}_unit"]) for m in metrics), ln["units"]]
            for label, lines in groups.items() for ln in lines]
    fig = _ratio_plot(_series(groups), seconds, metrics)
    return report.add(f"""## Side by side

Per run and budget, the method named for it, or else the method with the lowest validation-unit loss
in that run (held-out units never choose it), and its ratio to each held-out unit's own per-unit
model: mean over distinct units [95% bootstrap interval over units].

{table(['run', f'budget [{unit}]', 'method', 'robot-s',
        *(f'{m.name} ratio' for m in metrics), 'units'], body)}

{report.figure(fig, "ratio_by_run.png", "ratio to the per-unit models by run")}
""")


def _series(groups: dict[str, list[dict[str, Any]]]) -> dict[str, list[dict[str, Any]]]:
    """One line of a figure per run, or per run and plan strategy where a run chose for several
    (its label-free budget 0 heads each)."""
    out: dict[str, list[dict[str, Any]]] = {}
    for label, lines in groups.items():
        strategies = sorted({ln["strategy"] for ln in lines if ln["strategy"] is not None})
        if len(strategies) <= 1:
            out[label] = lines
            continue
        for st in strategies:
            out[f"{label} `{st}`"] = [ln for ln in lines if ln["strategy"] in (None, st)]
    return out


def pooled_section(provenance: dict[str, Any]) -> str:
    """Which runs a pooled report (`anytip report RUN RUN ... --out DIR`) holds, and how their specs
    differ from the first run's (whose spec the text above describes); empty for one run."""
    pooled = provenance.get("pooled_from")
    if not pooled:
        return ""
    body = [[f"`{p['run']}`", ", ".join(map(str, p["seeds"])), p["held_out_units"],
             "; ".join(f"`{k}`: `{v}`" for k, v in p["differs"].items()) or "same spec"] for p in pooled]
    return f"""
This report pools {len(pooled)} runs (folds or seeds run apart), each held-out unit scored in one of
them against its own per-unit model; each budget's method is the one with the lowest validation loss
averaged over every run's seeds.

{table(['run', 'seeds', 'held-out units', 'spec differs from the first run in'], body)}
"""


def _shape_text(ctx: Any, opts: Any) -> str:
    """Which MLP each method's figures come from: the shared models' shape, where
    `options.shared_model` sets one, differs from the reference's."""
    ref = " -> ".join(map(str, ctx.spec.model.sizes))
    shape = opts.shared_shape(ctx.spec.model, ctx.spec.name, str(ctx.provenance.get("sensor_model")))
    others = ("" if not opts.reference_shapes else " Rows `per_unit:<sizes>` are per-unit models of other "
              "shapes (`options.reference_shapes`), trained and selected exactly like the reference.")
    if shape.sizes == ctx.spec.model.sizes:
        return f"`adapted:*` models are scored after folding into the plain {ref} MLP.{others}"
    return (f"`adapted:*` and `pooled` models are a {' -> '.join(map(str, shape.sizes))} MLP "
            f"(`options.shared_model`), scored after folding their adapters into it; the per-unit "
            f"reference and `scratch` are the {ref} MLP.{others}")


def own_check_section(cross_sensor: dict[str, Any]) -> str:
    """How the calibration's own check (`anytip calibrate`'s bad-unit alarm) behaves on the
    held-out units, which are ordinary units: each one's check over the worst validation
    unit's, per shared model and budget, pooled over seeds. Empty when no run recorded one."""
    ratios: dict[tuple[str, str], list[float]] = {}
    alarm, folds = None, None
    for record in cross_sensor.values():
        own = record.get("own_check") or {}
        alarm = own.get("alarm_above", alarm)
        folds = own.get("folds", folds)
        val = set(own.get("validation_units", []))
        for model, by_budget in (own.get("by_shared_model") or {}).items():
            for budget, losses in by_budget.items():
                worst = max((v for u, v in losses.items() if u in val and v is not None), default=None)
                if worst:
                    ratios.setdefault((model, budget), []).extend(
                        v / worst for u, v in losses.items() if u not in val and v is not None)
    if not ratios or alarm is None:
        return ""
    body = [[f"`{model}`", budget, len(r), f"{np.median(r):.2f}x", f"{max(r):.2f}x",
             sum(x > alarm for x in r)] for (model, budget), r in ratios.items() if r]
    return f"""
## The calibration's own check on ordinary units

`anytip calibrate` {_check_text(folds)}, and warns when the result is more than {alarm:g}x
the worst of the shared model's validation units checked the same way. The held-out units
here are ordinary units: how often would the alarm have fired on them (unit-seeds pooled)?

{table(['shared model', 'budget', 'held-out unit-seeds', 'median check / worst validation',
        'largest', f'alarms (> {alarm:g}x)'], body)}
"""


COVERAGE_BAND = 0.05  # a unit-output's coverage counts as on target within +-0.05 of the nominal level
# (label, row-field prefix) of each half-width rows may score (`pipelines.cross_sensor_jobs.interval_fields`)
INTERVAL_KINDS = (("own plan", ""), ("own plan x fleet factor", "fleet_"),
                  ("own plan x fleet factor x its leave-one-out margin", "margin_"),
                  ("validation units' (plan unused)", "typical_"),
                  ("geometric mean of the two above", "shrunk_"),
                  ("network of the transferred rows alone, on the plan x its factor", "transfer_"))


def interval_section(rows: list[dict[str, Any]], units: dict[str, str] | None = None) -> str:
    """Coverage of the intervals each held-out unit gets from its own plan (`options.intervals`),
    and, where the run learnt a fleet factor, of the other `INTERVAL_KINDS`, per method and
    budget over unit-seed-outputs: how many lie within the band around the nominal level, the
    lowest, the median, and the mean half-width of each output, headed with its unit where `units`
    ({output: unit}, `output_units`) names it. Empty without them."""
    groups: dict[tuple[str, float], list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        if r.get("interval_level") is not None:
            groups[(r["method"], budget_of(r))].append(r)
    if not groups:
        return ""
    first = next(iter(groups.values()))[0]
    names = [k.removesuffix("_coverage") for k in first if k.endswith("_coverage")
             and not k.endswith(tuple(f"_{prefix}coverage" for _, prefix in INTERVAL_KINDS if prefix))]
    level = first["interval_level"]
    body = []
    for (method, budget), rs in sorted(groups.items(), key=lambda kv: (kv[0][1], kv[0][0])):
        for label, prefix in INTERVAL_KINDS:
            if all(f"{n}_{prefix}coverage" in r for r in rs for n in names):
                body.append([f"`{method}`", f"{budget:g}", label, *_coverage_cells(rs, names, prefix, level)])
    lo, hi = level - COVERAGE_BAND, level + COVERAGE_BAND
    return f"""
## Intervals from each unit's own plan

Each held-out unit's {level:.0%} interval is its calibrated prediction +- a half-width per output:
the split-conformal quantile of its plan's out-of-fold residuals (the plan's presses dealt into
folds, each predicted by the adapter refitted without it; `options.intervals`). For `response@`
rows the residuals are those of the unit's network on its plan's own rows, which also trained it
(a network per fold would cost a response transfer as much again per fold). The fleet factor
(where recorded) is what the validation units taught: per output, the geometric mean over them of
the half-width their test rows needed over the one their own plan gave; `anytip calibrate`
applies the factor its shared model records. The third kind ignores the unit's plan: every
held-out unit gets the validation units' typical half-width (the geometric mean of what their
test rows needed), which separates how much the unit's own plan tells from noise in it; the
geometric mean of the fleet-corrected and the validation units' half-widths shrinks the unit's
plan halfway to the fleet.
Coverage is the share of the unit's test rows inside, per output; a unit-seed-output is on
target within [{lo:.2f}, {hi:.2f}]. A unit's test set holds few independent pieces (its test
patches), so even a method whose coverage is exactly {level:.2f} for every unit lands outside that
band on some: "an exact method in it" is the share such a method would put inside on the same test
sets (each unit's test patches drawn again; fleet-factor rows of runs that recorded it): what a
perfect per-unit interval would be expected to reach. Half-widths: mean over unit-seeds, in each
output's unit.

{table(['method', 'budget [robot-s]', 'half-width', 'unit-seed-outputs', f'in [{lo:.2f}, {hi:.2f}]',
        'an exact method in it', 'lowest',
        'median', 'fewest test rows', *(_with_unit(f'{n} half-width', (units or {}).get(n)) for n in names)],
       body)}
"""


def output_units(provenance: dict[str, Any]) -> dict[str, str]:
    """{output (label column): unit} from the targets a run recorded (`provenance["targets"]`: {target:
    {"unit": ..., "components": [...]}}); empty for a run that recorded none."""
    targets = provenance.get("targets") or {}
    return {c: t["unit"] for t in targets.values() for c in t.get("components", [])}


def _with_unit(head: str, unit: str | None) -> str:
    return head if unit is None else f"{head} [{unit}]"


def exact_share(rows: list[dict[str, Any]]) -> float | None:
    """The share of fleet-factor unit-outputs that a method exactly calibrated for every unit would
    put in the band on these rows' test sets: the mean of 1 - `<output>_exact_p_outside`
    (`pipelines.cross_sensor_jobs.test_set_fields`); None unless every such unit-output has it."""
    exact = [1 - v for r in rows for k, v in r.items() if k.endswith("_exact_p_outside")]
    n = sum(k.endswith("_fleet_coverage") for r in rows for k in r)
    return float(np.mean(exact)) if exact and len(exact) == n else None


def _coverage_cells(rs: list[dict[str, Any]], names: list[str], prefix: str, level: float) -> list[Any]:
    cover = np.array([[r[f"{n}_{prefix}coverage"] for n in names] for r in rs])
    inside = np.abs(cover - level) <= COVERAGE_BAND + 1e-12
    exact = exact_share(rs) if prefix == "fleet_" else None
    decided = "" if exact is None else f"{exact:.0%}"
    return [cover.size, f"{inside.mean():.0%}", decided, f"{cover.min():.3f}", f"{np.median(cover):.3f}",
            int(np.min([r["interval_test_rows"] for r in rs])),
            *(f"{np.mean([r[f'{n}_{prefix}halfwidth'] for r in rs]):.3g}" for n in names)]


def _check_text(folds: int | None) -> str:
    """How the recorded own check was computed: press folds, or (runs that recorded no folds)
    the earlier check on every 5th press alone."""
    if folds is None:
        return "refits a new unit's adapter without every 5th press of its plan and scores those presses"
    return (f"deals a new unit's plan into {folds} folds of whole presses, predicts each fold with the "
            "adapter refitted without it and scores all the plan's rows so predicted")


def _extra_text(provenance: dict[str, Any]) -> str:
    """The report's sentence on training-only units from another registry, if any."""
    extra = provenance.get("extra_units")
    if not extra:
        return ""
    return (f" Every model this run trains across units (shared models, the response model) also "
            f"trains on {len(extra['units'])} units of registry `{extra['registry']}` "
            f"(`options.extra_units`; training only, no unit in common).")


def _budget_text(opts: Any, seconds: bool) -> str:
    """How a budget becomes a calibration (for the report's reader)."""
    if not seconds:
        return (f"A budget is the first N contact rows of the unit's `{opts.calibration_protocol}` "
                "calibration stream (test patches removed); seconds are robot time into that stream.")
    rig = opts.rig
    return (f"A budget is robot seconds of whole presses from the unit's calibration runs "
            f"(`{opts.calibration_protocol or 'all runs'}`, test patches removed), chosen by "
            f"{', '.join(f'`{s}`' for s in opts.plan_strategies)} (method suffix `@strategy`; "
            f"data/plans.py). Robot time counts each press, a {rig.move_s:g} s move before it "
            f"and {rig.remount_s:g} s per change of orientation; the adapter prior is scaled by "
            f"{rig.effective_hz:g} effective samples per contact second.{_designed_text(opts)}")


def _designed_text(opts: Any) -> str:
    """Which designed runs strategy `designed` reads (empty where the run has no such strategy)."""
    if "designed" not in opts.plan_strategies:
        return ""
    scale = opts.designed_scale
    which = "each budget" if scale == 1.0 else f"{scale:g} times each budget (`options.designed_scale`)"
    return (f" `designed` takes the unit's runs of the designed plan of {which} (`plan<seconds>`), "
            "its presses in the test patches left out, in recorded order up to the budget.")
