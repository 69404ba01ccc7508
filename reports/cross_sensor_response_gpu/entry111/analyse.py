"""Research log entry 111: the recipe's intervals on 64 fresh units (SIM43-*, never simulated before), each
tested on both its sessions, under entry 106's folds and learners. Prints rule 1 (the gate: 32 distinct
SIM43 units per fold and method with the override recorded and each unit's test rows 1.5-2.5 times its main
rows alone; and, not gating, the 24 factor units' learner records against entry 110's `fleet88r_both`),
rule 2 (the target per method with its verdict) and, deciding nothing, the first runs (main rows alone),
each fold's factors and margins, the lowest coverage and an exact method's share in band. The fresh units
have no per-unit references, so no ratio to them is printed. From the repository root:

    python reports/cross_sensor_response_gpu/entry111/analyse.py
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path
from typing import Any

import numpy as np

from anytip.rundir import read_json

G = Path("reports/cross_sensor_response_gpu")
RUNS = [G / f"entry111/fleet88x_seed{k}" for k in (0, 1)]
ONE_SESSION = [G / f"entry111/one_session_seed{k}" for k in (0, 1)]  # the first runs: main rows alone
SAME_LEARNERS = [G / f"entry110/fleet88r_both/fleet88_seed{k}" for k in (0, 1)]
OVERRIDE = "splits.test_rows=all_sessions"
PREFIX, PER_FOLD = "SIM43-", 32
ANALYSE_106 = runpy.run_path(str(G / "entry106/analyse.py"))  # factors
ANALYSE_108 = runpy.run_path(str(G / "entry108/analyse.py"))  # METHODS, OUTPUTS, band edges
ANALYSE_110 = runpy.run_path(str(G / "entry110/analyse.py"))  # met
METHODS, OUTPUTS = ANALYSE_108["METHODS"], ANALYSE_108["OUTPUTS"]
FLOOR, LOW, HIGH = ANALYSE_108["FLOOR"], ANALYSE_108["LOW"], ANALYSE_108["HIGH"]


def fold_rows(run: Path, method: str) -> dict[str, dict[str, Any]]:
    """A fold's `method` rows (`rows.json`, as `entry107/fresh_held_out.py` writes them) by unit."""
    return {r["unit"]: r for r in read_json(run / "rows.json")["rows"] if r["method"] == method}


def rows_by_unit(runs: list[Path], method: str) -> dict[str, dict[str, Any]]:
    """Both folds' `method` rows by unit; a unit held out in both folds is an error."""
    out: dict[str, dict[str, Any]] = {}
    for run in runs:
        mine = fold_rows(run, method)
        if set(mine) & set(out):
            sys.exit(f"units held out twice: {sorted(set(mine) & set(out))}")
        out |= mine
    return out


def gate() -> bool:
    """Rule 1's gate: 32 distinct SIM43 units per fold and method, the override recorded, and (added after
    the first runs read no test session) each unit's test rows 1.5-2.5 times its main rows alone."""
    ok = True
    for run, first in zip(RUNS, ONE_SESSION, strict=True):
        got = read_json(run / "rows.json")
        units = {m: fold_rows(run, m) for m in METHODS}
        fine = (OVERRIDE in got.get("overrides", [])
                and all(len(u) == PER_FOLD and all(k.startswith(PREFIX) for k in u) for u in units.values()))
        main = {m: fold_rows(first, m) for m in METHODS}
        ratio = np.array([r["interval_test_rows"] / main[m][u]["interval_test_rows"]
                          for m, rows in units.items() for u, r in rows.items()])
        fine &= bool(((ratio >= 1.5) & (ratio <= 2.5)).all())
        print(f"  {run.name}: {', '.join(f'{m} {len(u)} units' for m, u in units.items())}; overrides "
              f"{got.get('overrides')}; test rows over the main rows alone {ratio.min():.2f}-"
              f"{ratio.max():.2f}: {'holds' if fine else 'FAILS'}")
        ok &= fine
    return ok


def learner_records(run: Path, seed: int) -> dict[str, dict[str, Any]]:
    """The fold's learner records at `cover_informative`, 120 s, plan alone and with use, by unit."""
    header = read_json(run / f"models/response_seed{seed}.json")
    iv = header.get("meta", header)["intervals"]
    return {kind: iv[f"{kind}units_by_strategy"]["cover_informative"]["120"] for kind in ("", "use_")}


def factor_units_against_110() -> str:
    """Not gating: the factor units' learner records against entry 110's runs of today's code."""
    lines = []
    for seed, (run, other) in enumerate(zip(RUNS, SAME_LEARNERS, strict=True)):
        mine, theirs = learner_records(run, seed), learner_records(other, seed)
        val = set(read_json(run / "rows.json")["units"]["val"])
        for kind in mine:
            units = sorted(set(mine[kind]) - val)
            equal = sum(mine[kind][u] == theirs[kind].get(u) for u in units)
            lines.append(f"  fold {seed} {kind or 'plan '}records: {equal} of {len(units)} factor units "
                         f"equal to entry 110's")
    return "\n".join(lines)


def coverage(rows: dict[str, dict[str, Any]]) -> np.ndarray:
    """(units, outputs): each unit-output's coverage with the factor x margin half-width (`margin_`)."""
    return np.array([[r[f"{o}_margin_coverage"] for o in OUTPUTS] for r in rows.values()])


def verdict(rows: dict[str, dict[str, Any]], method: str) -> str:
    """Rule 2: met if at least 90% of the unit-outputs lie in the band and none below the floor (entry
    110's rule)."""
    return f"  verdict, {method}: {'met' if ANALYSE_110['met'](rows) else 'missed'}"


def summary(rows: dict[str, dict[str, Any]], method: str) -> str:
    """Share in band, the unit-outputs below the floor, the lowest coverage and an exact method's share."""
    cover = coverage(rows)
    units = list(rows)
    low = [f"{units[i]} {OUTPUTS[d]} {cover[i, d]:.3f}"
           for i, d in zip(*np.nonzero(cover < FLOOR), strict=True)]
    i, d = np.unravel_index(np.argmin(cover), cover.shape)
    exact = ANALYSE_108["exact_share"](list(rows.values()))
    return (f"  {method}: {np.mean((cover >= LOW) & (cover <= HIGH)):.1%} of {cover.size} in [{LOW:.2f}, "
            f"{HIGH:.2f}], {len(low)} below {FLOOR:.2f} ({', '.join(low) or 'none'}); lowest "
            f"{cover[i, d]:.3f} ({units[i]} {OUTPUTS[d]}); an exact method {exact:.0%} in band")


def main() -> None:
    print("rule 1, the gate:")
    if not gate():
        sys.exit("rule 1 fails: nothing below is read")
    print("rule 1, also read (not gating):\n" + factor_units_against_110())
    print("\nrule 2, the target on both sessions' rows of the fresh units:")
    for m in METHODS:
        print(summary(rows_by_unit(RUNS, m), m))
    for m in METHODS:
        print(verdict(rows_by_unit(RUNS, m), m))
    print("\nalso read (decides nothing): the first runs, every fresh unit on its main rows alone (the code "
          "before fleet_groups)")
    for m in METHODS:
        rows = rows_by_unit(ONE_SESSION, m)
        print(summary(rows, m))
        print(verdict(rows, m))
    print("\nalso read (decides nothing): each fold's factors and margins")
    for seed, run in enumerate(RUNS):
        print(ANALYSE_106["factors"](run, seed))


if __name__ == "__main__":
    main()
