"""Research log entry 143's reading: today's recipe at 600 s on fleet88 with the chosen 600 s design.
Rule 1: the references' rows equal entry 122's, every plan costs at most 600 s, and the designed plans are
entry 139's (`fleet88f`) up to the recorded-lead pricing. Rule 2: both plans at 600 s, alone and with
ordinary use. Rule 3: designed over `cover_informative`, and today's recipe over entry 26's (entry 139),
paired per unit. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry143/analyse.py
"""

import runpy
from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
READING = runpy.run_path(str(HERE.parent / "entry122" / "analyse.py"))  # entry 121's and 122's helpers
E122, E139 = HERE.parent / "entry122", HERE.parent / "entry139"
rows, record, line, KEYS, FOLDS, METHODS = (READING[n] for n in ("rows", "record", "line", "KEYS", "FOLDS",
                                                                  "METHODS"))
BUDGET = 600.0


def references(got: list[dict[str, Any]]) -> list[tuple[Any, ...]]:
    return sorted(tuple(sorted(r.items())) for r in got if r["method"] == "per_unit")


def gate(k: int) -> None:
    """Rule 1 for fold k."""
    got = rows(HERE, k)
    equal = references(got) == references(rows(E122, k))
    most = max(r["calib_seconds"] for r in got if r["method"] in METHODS)
    mine = {r["unit"]: (r["calib_samples"], r["calib_seconds"])
            for r in got if r["method"] == "response@designed"}
    before = {r["unit"]: (r["calib_samples"], r["calib_seconds"])
              for r in read_json(E139 / f"fleet88f_seed{k}" / "metrics.json")["results"]
              if r["method"] == "response@designed"}
    more = [mine[u][0] - before[u][0] for u in mine]
    print(f"rule 1, fold {k}: references {'equal' if equal else 'DIFFER'} to entry 122's; "
          f"the plans cost at most {most:.1f} s; designed plans of {len(mine)} units against entry 139's: "
          f"rows {min(more):+d} to "
          f"{max(more):+d}, robot seconds {min(m[1] for m in mine.values()):.1f}-"
          f"{max(m[1] for m in mine.values()):.1f} (entry 139: {min(b[1] for b in before.values()):.1f}-"
          f"{max(b[1] for b in before.values()):.1f})")


def per_unit(got: list[dict[str, Any]], method: str) -> dict[str, dict[str, float]]:
    """Per output kind, per unit: the method's ratio at 600 s."""
    return {label: unit_ratios(got, key)[(method, BUDGET)] for label, key in KEYS.items()}


def rmse(got: list[dict[str, Any]], method: str, key: str) -> dict[str, float]:
    return {r["unit"]: r[key] for r in got if r["method"] == method}


def main() -> None:
    for k in FOLDS:
        gate(k)
    mine = [r for k in FOLDS for r in rows(HERE, k)]
    e26 = [r for k in FOLDS
           for r in read_json(E139 / f"fleet88f_seed{k}" / "metrics.json")["results"]]
    per = {m: per_unit(mine, m) for m in METHODS}
    print("rule 2, 600 s:")
    for m in METHODS:
        print(f"  {m}: {line(per[m])}")
        bounds = {label: mean_interval(list(v.values()))[2] for label, v in per[m].items()}
        print("    upper bounds to three places: "
              + ", ".join(f"{label} {b:.3f}" for label, b in bounds.items()))
    print(f"  entry 139's response@designed (entry 26's recipe): {line(per_unit(e26, 'response@designed'))}")
    print(f"  entry 139's response@cover (entry 26's recipe): {line(per_unit(e26, 'response@cover'))}")
    READING["READING"]["designed_over_informative"](per)
    print("rule 3, today's recipe over entry 26's (entry 139's fleet88f rows), paired per unit:")
    pairs = (("response@designed", "response@designed"), ("response+use@designed", "response@designed"),
             ("response@cover_informative", "response@cover"))
    for m, theirs in pairs:
        parts = []
        for label, key in KEYS.items():
            a, b = rmse(mine, m, key), rmse(e26, theirs, key)
            parts.append(f"{label} x{paired_text([a[u] / b[u] for u in sorted(a)])}")
        print(f"  {m} over {theirs}: " + ", ".join(parts))
    val = {m: np.mean([record(HERE, k)["val_loss"][m]["600"] for k in FOLDS]) for m in METHODS}
    print("validation, mean over the folds: " + ", ".join(f"{m} {v:.5f}" for m, v in val.items()))


if __name__ == "__main__":
    main()
