"""One table over the unit folds of a cross_sensor benchmark: the rows of several run directories
(each fold or seed its own run) together, as the reports compute them.

    python scripts/fold_table.py reports/cross_sensor_response_extra/fleet88_seed{0,1}

Per (method, budget): the ratio of each of the runs' two targets (the fingertip's force and angle, or
the targets the runs recorded, e.g. the edge sensor's depth and position) to each held-out unit's own
per-unit model, mean over distinct units with a 95% bootstrap interval over units
(`report.cross_sensor.summary`), the share of units at or below 1.10x and below 1.0x in the first
target, and, where the rows carry intervals,
the share of unit-outputs whose fleet-factor interval covers [0.85, 0.95] of its test rows, the
lowest coverage and how many fall below 0.80, and the share that a method whose coverage is exactly
0.90 for every unit would put in that band on the same test sets (their test patches drawn again:
how far the test sets can decide the target).

`--against B1 B2 ...` compares the runs with other runs of the same held-out units and references
(e.g. a rescoring): per (method, budget), the geometric mean over units of each unit's RMSE of each
target in the runs over its RMSE in B, with a 95% bootstrap interval over units. With
`--test-rows-moved` the runs test the same units on other rows (a test session, entry 63): their
references differ, and pair as well (`per_unit -1 s`).

`--ceiling`, where rows record the half-widths their test rows needed: per (method, budget) the
most unit-outputs one factor per output, chosen on these very units, could put in the band, and the
most with none below the floor. A diagnostic of what any fleet factor can reach, never a method.

`--pooled` (entry 53), for folds of response transfer: each fold's factor and leave-one-out margin
learnt by the validation (and factor) units of every fold, as their folds' response models recorded
them, except the units this fold holds out; per (method, budget) the share of held-out unit-outputs
whose pooled interval lies in the band and how many fall below the floor, with each fold's number of
learners, factor and margin, and a check that the fold's own learners give the factor its rows used.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from anytip.calibrate import response_models
from anytip.models.io import model_paths
from anytip.pipelines.common import recorded_metrics
from anytip.pipelines.cross_sensor_jobs import band_edges, needed_key
from anytip.report.cross_sensor import (
    METRICS,
    budget_of,
    exact_share,
    paired_text,
    ratio_text,
    summary,
    unit_ratios,
)
from anytip.report.metric import Metric
from anytip.rundir import read_json
from anytip.uncertainty.fleet_margin import Learner, factor_ceiling, pooled_factor

# which learner records of a response model a row's method reads: ordinary use or the plan alone
LEARNER_KEYS = {"response": "units_by_strategy", "response+use": "use_units_by_strategy"}
Fold = tuple[str, int]  # (run directory, seed): one response model and the units it holds out


def edges_of(rows: list[dict[str, Any]]) -> tuple[float, float, float]:
    """The floor and band edges of the rows' interval level (`band_edges`; 0.9 where no row has
    intervals): the issue's target is every unit-output above the floor, most in the band."""
    levels = {r["interval_level"] for r in rows if r.get("interval_level") is not None}
    if len(levels) > 1:
        sys.exit(f"the runs' intervals have several levels {sorted(levels)}; tabulate one at a time")
    return band_edges(levels.pop() if levels else 0.9)


def rows_of(runs: list[Path]) -> list[dict[str, Any]]:
    """Every run's rows; a unit held out in two runs is an error (folds hold each unit out once)."""
    rows, seen = [], {}
    for run in runs:
        mine = read_json(run / "metrics.json")["results"]
        for u in {r["unit"] for r in mine if r["method"] == "per_unit"}:
            if u in seen:
                sys.exit(f"unit {u} is held out in {seen[u]} and in {run}")
            seen[u] = run
        rows += mine
    return rows


def coverage_cells(rows: list[dict[str, Any]], kind: str = "fleet") -> str:
    """In-band share, lowest and count below the floor of the `kind` intervals' coverage (`fleet`: the
    fleet factor's; `margin`: times its leave-one-out margin), and
    the share a method exactly calibrated for every unit would put in the band on the same test sets
    (the mean over unit-outputs of 1 - `<output>_exact_p_outside`; blank for rows without it)."""
    cov = [v for r in rows for k, v in r.items() if k.endswith(f"_{kind}_coverage")]
    if not cov:
        return "| | | |"
    c = np.asarray(cov)
    floor, low_edge, high_edge = edges_of(rows)
    share = np.mean((c >= low_edge) & (c <= high_edge))
    exact = exact_share(rows)
    decided = "" if exact is None else f"{exact:.0%}"
    low = f"{c.min():.3f}, {int((c < floor).sum())} below {floor:.2f}"
    return f"| {share:.0%} of {len(c)} | {low} | {decided} |"


def metrics_of(runs: list[Path]) -> Sequence[Metric]:
    """The runs' two targets as report columns, from the targets the first run recorded (the
    fingertip's force and angle where it recorded none)."""
    path = runs[0] / "provenance.json"
    targets = read_json(path).get("targets") if path.is_file() else None
    return recorded_metrics(targets)


def table(rows: list[dict[str, Any]], kind: str = "fleet", metrics: Sequence[Metric] = METRICS) -> str:
    first, second = metrics[:2]
    per_first = unit_ratios(rows, first.key)
    band = "[{1:.2f}, {2:.2f}]".format(*edges_of(rows))
    lines = [f"| method | robot-s | units | {first.name} ratio [95%] | {second.name} ratio [95%] | "
             f"{first.name} <= 1.10x / < 1.0x | intervals in {band} | lowest coverage | "
             f"an exact method in {band} |",
             "|---|---|---|---|---|---|---|---|---|"]
    for s in summary(rows, metrics):
        if s["method"] == "per_unit":
            continue
        per_unit = np.asarray(list(per_first.get((s["method"], s["budget"]), {}).values()))
        mine = [r for r in rows if r["method"] == s["method"] and budget_of(r) == s["budget"]]
        lines.append(f"| {s['method']} | {s['budget']:g} | {s['units']} | "
                     f"{ratio_text(s[f'{first.name}_unit'])} | {ratio_text(s[f'{second.name}_unit'])} | "
                     f"{np.mean(per_unit <= 1.10):.0%} / "
                     f"{np.mean(per_unit < 1.0):.0%} {coverage_cells(mine, kind)}")
    return "\n".join(lines)


def ceilings(rows: list[dict[str, Any]]) -> str:
    """Per (method, budget) whose rows record needed half-widths: the most unit-outputs one factor
    per output could put in the band over these units, free and with none below the floor
    (`uncertainty.fleet_margin.factor_ceiling`), and the factors of the latter."""
    edges = edges_of(rows)
    lines = []
    for method, budget in sorted({(r["method"], budget_of(r)) for r in rows if r["method"] != "per_unit"}):
        mine = [r for r in rows if r["method"] == method and budget_of(r) == budget]
        names = [k[:-len("_fleet_halfwidth")] for k in mine[0] if k.endswith("_fleet_halfwidth")]
        if not names or any(needed_key(n, e) not in r for r in mine for e in edges for n in names):
            continue
        own = np.array([[r[f"{n}_halfwidth"] for n in names] for r in mine])
        floor, low, high = (np.array([[r[needed_key(n, e)] for n in names] for r in mine]) for e in edges)
        c = factor_ceiling(own, floor, low, high)
        factors = ", ".join(f"{n} {f:.2f}" for n, f in zip(names, c.safe, strict=True))
        lines.append(f"{method} {budget:g} s, {len(mine)} units: one factor per output puts at most "
                     f"{c.free_in_band:.0%} in the band, {c.safe_in_band:.0%} with none below {edges[0]:.2f} "
                     f"({factors})")
    return "\n".join(lines)


def fold_learners(runs: list[Path]) -> dict[Fold, dict[tuple[str, str, str], dict[str, Learner]]]:
    """Per fold, (learner key, strategy, budget label) -> {unit: its Learner} as the fold's response
    model recorded them (`calibrate.response_models`, the metadata's `intervals`)."""
    out = {}
    for run in runs:
        for seed, path in response_models(run).items():
            recorded = read_json(model_paths(path)[1]).get("meta", {}).get("intervals") or {}
            out[str(run), seed] = {
                (key, strategy, budget): {u: Learner.from_record(rec, list(rec["own"]))
                                          for u, rec in units.items()}
                for key in LEARNER_KEYS.values() for strategy, by_budget in recorded.get(key, {}).items()
                for budget, units in by_budget.items()}
    return out


def pooled(runs: list[Path]) -> str:
    """Per (method, budget) of response transfer: the held-out unit-outputs whose interval, each fold's
    own half-width times the factor and margin of every fold's learners but its own held-out units
    (`uncertainty.fleet_margin.pooled_factor`), lies in the band, and those below the floor."""
    tagged = [(str(run), r) for run in runs for r in read_json(run / "metrics.json")["results"]]
    floor, low, high = needed_edges = edges_of([r for _, r in tagged])
    held = {}
    for run, r in tagged:
        if r["method"] == "per_unit":
            held.setdefault((run, r["seed"]), set()).add(r["unit"])
    learners = fold_learners(runs)
    lines = []
    for method, budget in sorted({(r["method"], budget_of(r)) for _, r in tagged if "@" in r["method"]}):
        base, strategy = method.split("@", 1)
        key = (LEARNER_KEYS.get(base), strategy, f"{budget:g}")
        mine = [(run, r) for run, r in tagged if r["method"] == method and budget_of(r) == budget]
        names = [k[:-len("_fleet_halfwidth")] for k in mine[0][1] if k.endswith("_fleet_halfwidth")]
        if key[0] is None or not names or any((run, r["seed"]) not in learners for run, r in mine):
            continue
        in_band, below, folds, drift = [], 0, {}, 0.0
        for run, r in mine:
            fold = (run, r["seed"])
            pool = {f"{u} ({f[0]} seed {f[1]})": x for f, by_key in learners.items()
                    for u, x in by_key.get(key, {}).items() if u not in held[fold]}
            if len(pool) < 2:
                continue
            factor, choice = pooled_factor(list(pool.values()))
            own, _ = pooled_factor(list(learners[fold][key].values()))
            used = np.array([r[f"{n}_fleet_halfwidth"] / r[f"{n}_halfwidth"] for n in names])
            drift = max(drift, float(np.max(np.abs(own / used - 1))))
            folds[fold] = f"{len(pool)} learners, margin {choice.margin:g}, factor " + \
                ", ".join(f"{n} {v:.2f}" for n, v in zip(names, factor, strict=True))
            width = np.array([r[f"{n}_halfwidth"] for n in names]) * factor * choice.margin
            edge = {e: np.array([r[needed_key(n, e)] for n in names]) for e in needed_edges}
            in_band += list((width >= edge[low]) & (width <= edge[high]))
            below += int((width < edge[floor]).sum())
        if in_band:
            share = f"{np.mean(in_band):.0%} of {len(in_band)} unit-outputs in [{low:.2f}, {high:.2f}]"
            lines += [f"{method} {budget:g} s, pooled factor x margin: {share}, {below} below {floor:.2f}; "
                      f"each fold's own learners give its rows' factor to {drift:.1e}"]
            lines += [f"  {run} seed {seed}: {text}" for (run, seed), text in folds.items()]
    return "\n".join(lines)


def ratios_text(pairs: list[tuple[dict[str, Any], dict[str, Any]]],
                metrics: Sequence[Metric] = METRICS) -> str:
    """`force x.. [..], angle x.. [..]` (each target's): the geometric mean over units of each pair's
    RMSE ratio."""
    return ", ".join(f"{m.name} x{paired_text([x[m.key] / y[m.key] for x, y in pairs])}" for m in metrics)


def paired(rows: list[dict[str, Any]], against: list[dict[str, Any]], moved: bool = False,
           metrics: Sequence[Metric] = METRICS) -> str:
    """Per (method, budget) both hold: the geometric mean over units of rows' RMSE over against's,
    force and angle [95%]; the units' references must be the same in both, unless the runs test the
    same units on other rows (`moved`, a test session: entry 63), where the references pair too."""
    refs = {r["unit"]: r[metrics[0].key] for r in rows if r["method"] == "per_unit"}
    other = {r["unit"]: r[metrics[0].key] for r in against if r["method"] == "per_unit"}
    if not moved and any(other.get(u) != f for u, f in refs.items()):
        sys.exit("--against: the runs' per-unit references differ; pair runs of the same units and "
                 "references (or give --test-rows-moved)")
    keep = (lambda m: True) if moved else (lambda m: m != "per_unit")
    b = {(r["method"], budget_of(r), r["unit"]): r for r in against if keep(r["method"])}
    lines = []
    for method, budget in sorted({(r["method"], budget_of(r)) for r in rows if keep(r["method"])}):
        mine = [(r, b[method, budget, r["unit"]]) for r in rows
                if r["method"] == method and budget_of(r) == budget and (method, budget, r["unit"]) in b]
        if not mine:
            continue
        lines.append(f"{method} {budget:g} s, {len(mine)} units: {ratios_text(mine, metrics)}")
    return "\n".join(lines)


def paired_strategies(rows: list[dict[str, Any]], mine: str, theirs: str,
                      metrics: Sequence[Metric] = METRICS) -> str:
    """Each `<method>@mine` row over the same unit's `<method>@theirs` row at the same budget, in the
    same runs: the geometric mean over units, force and angle [95%] (entry 58)."""
    b = {(r["method"], budget_of(r), r["unit"]): r for r in rows}
    lines = []
    found = {(r["method"], budget_of(r)) for r in rows if r["method"].endswith(f"@{mine}")}
    for method, budget in sorted(found):
        other = method.removesuffix(f"@{mine}") + f"@{theirs}"
        pairs = [(r, b[other, budget, r["unit"]]) for r in rows
                 if r["method"] == method and budget_of(r) == budget and (other, budget, r["unit"]) in b]
        if pairs:
            lines.append(f"{method} over {other}, {budget:g} s, {len(pairs)} units: "
                         f"{ratios_text(pairs, metrics)}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", type=Path, nargs="+", help="finished cross_sensor run directories")
    parser.add_argument("--against", type=Path, nargs="+", default=[], help="runs to pair the runs with")
    parser.add_argument("--intervals", choices=("fleet", "margin"), default="fleet",
                        help="which intervals' coverage: the fleet factor's, or times its margin (entry 50)")
    parser.add_argument("--ceiling", action="store_true",
                        help="the most one factor per output could put in the band on these units (entry 51)")
    parser.add_argument("--pooled", action="store_true",
                        help="each fold's factor learnt by every fold's learners but its held-out units "
                             "(entry 53)")
    parser.add_argument("--test-rows-moved", action="store_true",
                        help="with --against: the runs test the same units on other rows (a test session), "
                             "so their references differ; pair every method's RMSE, the references' too")
    parser.add_argument("--strategies", nargs=2, metavar=("MINE", "THEIRS"),
                        help="pair each <method>@MINE row with the same unit's <method>@THEIRS row")
    args = parser.parse_args(argv)
    rows, metrics = rows_of(args.runs), metrics_of(args.runs)
    print(table(rows, args.intervals, metrics))
    if args.ceiling:
        print("\n" + ceilings(rows))
    if args.pooled:
        print("\n" + pooled(args.runs))
    if args.against:
        print("\n" + paired(rows, rows_of(args.against), args.test_rows_moved, metrics))
    if args.strategies:
        print("\n" + paired_strategies(rows, *args.strategies, metrics=metrics))
    return 0


if __name__ == "__main__":
    sys.exit(main())
