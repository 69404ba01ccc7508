"""Research log entry 199's reading: the 90% intervals of `anytip calibrate --plan-strategy designed
--use-log` (120 s, a log lighter than the benchmark's use: the plan alone's factor since entry 198) with
the factor of the unit's own fold's run (A, today's default) and with the factor pooled over every fold's
run of its registry, as `--factor-from` pools it (P: the plan-alone learners of all the runs' response
models but the unit's own, their factor and the margin they choose, `calibrate.intervals.pooled_learners`,
`pooled_factor`). Each applied to the calibration's recorded own half-widths and scored on the unit's full
runs, on entry 198's units: 64 fresh validation units (entry 191's arm H), which decide, and 32 held-out
units (entries 182 and 186), read after.

    python reports/cross_sensor_response_gpu/entry199/analyse.py > \\
        reports/cross_sensor_response_gpu/entry199/logs/analyse.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

from anytip.calibrate.intervals import interval_records, pooled_learners
from anytip.data.registry import Registry
from anytip.models.io import RESPONSE_FORMAT, model_paths, read_header
from anytip.uncertainty.conformal import coverage, interval
from anytip.uncertainty.fleet_margin import pooled_factor

HERE = Path(__file__).parent
E198 = runpy.run_path(str(HERE.parent / "entry198" / "analyse.py"))
G = HERE.parent
FOLDS = {"entry147": [G / "entry147" / "at120" / f"fleet88_seed{k}" for k in range(2)],
         "entry146": [G / "entry146" / "at120" / "other16_severe_d0" / f"other16_seed{k}" for k in range(4)]}


def pooled(response_model: Path, unit: str, names: tuple[str, ...]) -> tuple[np.ndarray, float, int]:
    """The factor (D,) `anytip calibrate --factor-from` gives a unit under `response_model` with every other
    fold's run of its registry listed, its margin included, the margin and the number of learners."""
    runs = next(r for key, r in FOLDS.items() if key in str(response_model))
    own = read_header(model_paths(response_model)[1], RESPONSE_FORMAT)["meta"]["intervals"]
    others = interval_records(runs, response_model)  # every run's models but this one
    learners = pooled_learners([(Path("."), own), *others], "units", E198["STRATEGY"], E198["BUDGET"], 0.9,
                               names, unit)
    factor, choice = pooled_factor(learners)
    return factor * choice.margin, choice.margin, len(learners)


def arms(read: tuple) -> tuple[dict[str, np.ndarray], float, int]:
    """A's and P's coverage (D,) of a calibration read on its unit's full runs (entry 198's `FullRuns`), P's
    margin and its number of learners."""
    model = Path(read.meta["response_model"])
    alone = E198["factors"](str(model), read.rec["unlabeled_seconds"])[0]["A"]
    got, margin, n = pooled(model, read.rec["unit"], read.names)
    both = {"A": alone, "P": got}
    covered = {arm: coverage(*interval(read.pred, read.own * f), read.target) for arm, f in both.items()}
    return covered, margin, n


def coverages(calibration: Path, registry: Registry) -> tuple[dict[str, np.ndarray], float, int]:
    """`arms` of the calibration directory."""
    return arms(E198["on_full_runs"](calibration, registry))


def main() -> None:
    totals: dict[str, dict[str, list[np.ndarray]]] = {}
    for name, pattern, root, role in E198["SETS"]:
        registry = Registry(root)
        found = sorted(p for p in Path().glob(pattern) if p.is_dir())
        per_arm: dict[str, list[np.ndarray]] = {"A": [], "P": []}
        margins, counts = [], []
        for calibration in found:
            cov, margin, n = coverages(calibration, registry)
            margins.append(margin)
            counts.append(n)
            for a, c in cov.items():
                per_arm[a].append(c)
        print(f"## {name} [{role}]: {len(found)} units; P's learners {min(counts)}-{max(counts)}, "
              f"margins {sorted(set(margins))}")
        for a, got in per_arm.items():
            print(f"  {a}: {E198['summary'](np.array(got))}")
            totals.setdefault(role, {}).setdefault(a, []).extend(got)
    for role, per_arm in totals.items():
        print(f"## all {role} units")
        for a, got in per_arm.items():
            print(f"  {a}: {E198['summary'](np.array(got))}")


if __name__ == "__main__":
    main()
