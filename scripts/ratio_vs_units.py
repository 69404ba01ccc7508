"""Cross-sensor ratio against the number of training units, across runs of one benchmark.

Each run is a finished cross_sensor run directory; its training units are the registry's
(`n_train_units`) plus those of `options.extra_units` (`n_extra_units`). The runs must share
their held-out units (the same spec and seed on the same registry), so the rows differ only
in what trained the shared models. For each method the script takes the force ratio to the
per-unit models per distinct held-out unit (mean over units, 95% bootstrap interval, as the
report computes it) and writes a markdown table and a figure:

    .venv/bin/python scripts/ratio_vs_units.py reports/cross_sensor_delta_prior \
        reports/cross_sensor_many_units/extra32 reports/cross_sensor_many_units/extra64 \
        reports/cross_sensor_many_units --out reports/cross_sensor_many_units/ratio_vs_units
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from anytip.errors import AnytipError
from anytip.report.cross_sensor import summary
from anytip.report.figures import save_figure, subplots
from anytip.report.markdown import table

METHODS = {  # (method, budget in robot seconds) -> legend
    ("adapted:input_stats", 0): "input statistics, 600 s unlabeled",
    ("pooled", 0): "pooled (tare only)",
    ("adapted:input_affine+film@spread", 120): "120 s, identity prior",
    ("adapted:input_affine+film/empirical@spread", 120): "120 s, empirical prior",
    ("adapted:input_affine+film/empirical@spread", 600): "600 s, empirical prior",
}


def load(run: Path) -> tuple[int, dict[tuple[str, int], tuple[float, float, float]], tuple[str, ...]]:
    """(training units, (method, budget) -> force ratio (mean, lower, upper), held-out units)."""
    rows = json.loads((run / "metrics.json").read_text())["results"]
    units = {r["n_train_units"] + r.get("n_extra_units", 0) for r in rows}
    if len(units) != 1:
        raise AnytipError(f"{run}: rows of several training-unit counts {sorted(units)}; one run per count")
    held = tuple(sorted({r["unit"] for r in rows if r["method"] == "per_unit"}))
    lines = {(s["method"], s["budget"]): s["force_unit"] for s in summary(rows)}
    return units.pop(), lines, held


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", type=Path)
    parser.add_argument("--out", type=Path, required=True, help="path stem for .md and .png")
    args = parser.parse_args()
    loaded = sorted(load(r) for r in args.runs)
    if len({held for _, _, held in loaded}) != 1:
        raise AnytipError("the runs hold out different units; compare runs of one spec and seed only")
    counts = [n for n, _, _ in loaded]
    body, fig_data = [], {}
    for key, label in METHODS.items():
        values = [lines.get(key) for _, lines, _ in loaded]
        if any(v is None for v in values):
            continue
        fig_data[label] = values
        body.append([label, *(f"{m:.2f}x [{lo:.2f}, {hi:.2f}]" for m, lo, hi in values)])
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.with_suffix(".md").write_text(table(["method", *(f"{n} units" for n in counts)], body) + "\n")
    fig, ax = subplots(1, 1, figsize=(6.4, 4.2))
    for label, values in fig_data.items():
        mean = [m for m, _, _ in values]
        err = [[m - lo for m, lo, _ in values], [hi - m for m, _, hi in values]]
        ax.errorbar(counts, mean, yerr=err, marker="o", capsize=3, label=label)
    ax.set_xscale("log", base=2)
    ax.set_xticks(counts, [str(n) for n in counts])
    ax.axhline(1.0, color="k", lw=0.8, ls=":")
    ax.set_xlabel("training units of the shared model")
    ax.set_ylabel("force RMSE / per-unit model's (95% CI over units)")
    ax.legend(fontsize=8)
    save_figure(fig, args.out.with_suffix(".png"))
    print(f"wrote {args.out.with_suffix('.md')} and {args.out.with_suffix('.png')}")


if __name__ == "__main__":
    main()
