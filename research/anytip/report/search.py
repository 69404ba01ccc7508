"""The search report: the Pareto front of the first target's error (the fingertip's force)
against MACs, the paper's MLP marked, and the front retrained on units the study never saw."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import matplotlib.ticker
import numpy as np

from anytip.report.figures import save_figure, subplots
from anytip.report.markdown import table as md_table
from anytip.report.metric import FINGERTIP_METRICS, Metric
from anytip.report.writer import Report

if TYPE_CHECKING:
    from pathlib import Path


PAPER_SIZES = (8, 12, 64, 64, 5)


def front_figure(trials: list[dict[str, Any]], path: Path, flash_max: int | None = None,
                 metrics: Sequence[Metric] = FINGERTIP_METRICS) -> Path:
    """Search-unit RMSE of the first metric against MACs and against flash bytes: every complete
    trial, the front members, the paper's MLP (star) and the flash limit."""
    fig, axes = subplots(1, 2, figsize=(11, 4.3), sharey=True)
    front = [t for t in trials if t["pareto"]]
    y = metrics[0].key
    objectives = ", ".join([*(m.name for m in metrics), "MACs"])
    for ax, key, label in zip(axes, ("macs", "flash_bytes"), ("MACs per inference", "flash bytes"),
                              strict=True):
        ax.scatter([t[key] for t in trials], [t[y] for t in trials], c="0.7", s=18,
                   label="trials within the budget")
        ax.scatter([t[key] for t in front], [t[y] for t in front], c="C0", s=30,
                   label=f"Pareto front ({objectives})")
        for t in trials:
            if t.get("paper", tuple(t["sizes"]) == PAPER_SIZES):
                ax.scatter([t[key]], [t[y]], marker="*", s=220, c="C3", label="paper MLP", zorder=5)
        if key == "flash_bytes" and flash_max:
            ax.axvline(flash_max, c="C3", ls="--", lw=1, label="flash budget")
        ax.set(xscale="log", xlabel=label)
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel(f"held-out {metrics[0].label}, search units")
    axes[1].legend(fontsize=8)
    fig.suptitle("architecture search under the budget")
    return save_figure(fig, path)


def by_architecture(rows: list[dict[str, Any]], metrics: Sequence[Metric] = FINGERTIP_METRICS
                    ) -> list[dict[str, Any]]:
    """Mean test-unit RMSE per retrained candidate (trial), under each metric's name."""
    groups: dict[tuple, list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        key = (r["method"], r.get("trial", tuple(r["sizes"])), r.get("activation"), r.get("features"))
        groups[key].append(r)
    out = []
    for (method, *_), rs in groups.items():
        out.append({"method": method, "sizes": tuple(rs[0]["sizes"]),
                    **{m.name: float(np.mean([r[m.key] for r in rs])) for m in metrics},
                    "calib_samples": int(np.mean([r["calib_samples"] for r in rs])),
                    "trial": rs[0].get("trial"),
                    **{k: rs[0].get(k) for k in ("activation", "features", "adapter")},
                    **{k: rs[0][k] for k in ("params", "macs", "flash_bytes", "ram_bytes", "measured")}})
    return sorted(out, key=lambda a: a["macs"])


def describe(a: dict[str, Any]) -> str:
    """'8-32-32-5 hardswish, neighbour_diffs[, adapter]'."""
    parts = [a.get("activation") or "relu", a.get("features") or "raw"]
    if a.get("adapter"):
        parts.append(a["adapter"])
    return f"{'-'.join(map(str, a['sizes']))} ({', '.join(parts)})"


def target(archs: list[dict[str, Any]], metric: Metric = FINGERTIP_METRICS[0]) -> str:
    """The search's target against the paper's MLP on the test units: 0.85x its RMSE of `metric`
    (the fingertip's force) at no more MACs, or its accuracy at half its MACs."""
    f, unit = metric.name, metric.label.rsplit("[", 1)[-1].rstrip("]")
    paper = next((a for a in archs if a["method"] == "paper_mlp"), None)
    if paper is None:
        return "The paper's MLP was not among the complete trials: no comparison."
    better = [a for a in archs if a["method"] == "search" and a["macs"] <= paper["macs"]
              and a[f] <= 0.85 * paper[f]]
    cheaper = [a for a in archs if a["method"] == "search" and a["macs"] <= 0.5 * paper["macs"]
               and a[f] <= paper[f]]
    if better or cheaper:
        a = (better or cheaper)[0]
        return (f"**Met**: {describe(a)} reaches {a[f]:.4g} {unit} against the paper's "
                f"{paper[f]:.4g} {unit} at {a['macs']} against {paper['macs']} MACs.")
    best = min((a for a in archs if a["method"] == "search"), key=lambda a: a[f], default=None)
    detail = "" if best is None else (f" The best front member on the test units, "
                                      f"{describe(best)}, reaches {best[f]:.4g} {unit} "
                                      f"at {best['macs']} MACs against the paper's {paper[f]:.4g} {unit} "
                                      f"at {paper['macs']}.")
    return f"**Not met** (>= 15% lower {f} RMSE at no more MACs, or equal at <= 50% MACs)." + detail


FAMILY_TEXT = {
    "per_unit": "Family `per_unit`: every unit gets its own network, trained on its own rows.",
    "shared": ("Family `shared`: one network trained on the training units with per-unit adapters; "
               "a search or test unit's adapter is fitted on the first {calib} labeled rows of its "
               "calibration stream, folded into a plain MLP of the deployed shape, and scored."),
}


def table_body(archs: list[dict[str, Any]], shared: bool, metrics: Sequence[Metric] = FINGERTIP_METRICS
               ) -> tuple[list[str], list[list[Any]]]:
    """Columns and rows of the test-unit table, each metric also as a ratio to the paper's MLP."""
    paper = next((a for a in archs if a["method"] == "paper_mlp"), None)
    head = ["method", "trial", "sizes", "activation", "features", *(["adapter"] if shared else []),
            "params", "MACs", "flash B", "RAM B", "bytes",
            *(h for m in metrics for h in (m.label, "vs paper"))]
    body = []
    for a in archs:
        ratios = [f"{a[m.name] / paper[m.name]:.2f}x" if paper else "n/a" for m in metrics]
        body.append([a["method"], a.get("trial"), "-".join(map(str, a["sizes"])),
                     a.get("activation") or "relu", a.get("features") or "raw",
                     *([a.get("adapter")] if shared else []), a["params"], a["macs"], a["flash_bytes"],
                     a["ram_bytes"], "measured" if a["measured"] else "estimated",
                     *(v for m, r in zip(metrics, ratios, strict=True) for v in (a[m.name], r))])
    return head, body


def write_report(ctx: Any, rows: list[dict[str, Any]], trials: list[dict[str, Any]],
                 budget: Any, metrics: Sequence[Metric] = FINGERTIP_METRICS) -> Path:
    s = ctx.provenance["search"]
    family = s.get("family", "per_unit")
    front_figure(trials, ctx.run_dir / "pareto.png", budget.flash_bytes_max, metrics)
    archs = by_architecture(rows, metrics)
    head, body = table_body(archs, family == "shared", metrics)
    names = " and ".join(m.name for m in metrics)
    skipped = "".join(f"\n- {line}\n" for line in ctx.provenance.get("skipped", []))
    calib = archs[0]["calib_samples"] if archs else 0
    tph = s["trials_per_hour"]
    secs = s.get("trial_seconds") or {}
    median = secs.get("complete")
    timing = "" if median is None else f"; a complete trial took {median:.1f} s (median)"
    train = f" ({len(s['train_units'])} training units)" if "train_units" in s else ""
    return Report(ctx.run_dir).add(f"""# {ctx.spec.name}: architecture search under the {budget.name} budget

{ctx.spec.description.strip()}

{FAMILY_TEXT[family].format(calib=calib)}

Budget: {budget.flash_bytes_max} B flash, {budget.ram_bytes_max} B RAM, inference within
{budget.inference_s_max * 1e3:.2f} ms at {budget.clock_hz / 1e6:.0f} MHz (constraints of every trial;
infeasible trials are pruned before training). Objectives: mean held-out {names}
RMSE of the {len(s['search_units'])} search units{train}, and MACs (the front is their
{len(metrics) + 1}-objective Pareto set; the figure shows its {metrics[0].name}-MACs view).
{s['trials']} trials ({s['complete']} complete) in
{s['wall_s']:.0f} s of study time (first trial start to last trial end)
with {s['workers']} worker(s): {'n/a' if tph is None else f'{tph:.0f}'} trials per hour on
`{ctx.provenance.get('device')}`{timing}.
Storage `{s['storage']}`, study `{s['study_name']}`.

![Pareto front](pareto.png)

## On units the study never saw

The paper's MLP (ReLU, raw pressures) and the front, retrained on the {len(s['test_units'])} test units
and scored on their held-out patches; ratios are to the paper's MLP in this run. `ablation` rows
are the front member most accurate on the search units with raw pressures instead of its input
features, or with ReLU instead of its activation (same widths, learning rate and batch size):

{md_table(head, body)}

{target(archs, metrics[0])}
{skipped}
Browse the study: `optuna-dashboard {s['storage']}`
""").write()
