"""Research log entry 112: the validation units calibrated apart from the held-out units (`fleet_groups`),
against entry 110's rescoring of the same folds from the code before (`fleet88r_both`, where they shared a
fleet per budget). Prints rule 1 (the 24 factor units' learner records, which were apart before too, against
the control's; the validation units' records, which should move), rule 2 (the held-out units' force and angle
RMSE, paired per unit against the control's: geometric mean and 95% bootstrap interval over the 88 units, per
method) and rule 3 (the interval target on both sessions' rows per method, each fold's factors and margins).
From the repository root:

    python reports/cross_sensor_response_gpu/entry112/analyse.py
"""

from __future__ import annotations

import runpy
from pathlib import Path

from anytip.report.cross_sensor import paired_text
from anytip.rundir import read_json

G = Path("reports/cross_sensor_response_gpu")
RUNS = [G / f"entry112/fleet88r_apart/fleet88_seed{k}" for k in (0, 1)]
CONTROL = [G / f"entry110/fleet88r_both/fleet88_seed{k}" for k in (0, 1)]
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
ANALYSE_106 = runpy.run_path(str(G / "entry106/analyse.py"))  # rows_by_unit, factors
ANALYSE_108 = runpy.run_path(str(G / "entry108/analyse.py"))  # intervals, METHODS
ANALYSE_111 = runpy.run_path(str(G / "entry111/analyse.py"))  # learner_records, verdict
rows_by_unit, METHODS = ANALYSE_106["rows_by_unit"], ANALYSE_108["METHODS"]


def learners() -> str:
    """Rule 1: per fold and kind, how many factor and validation units' records equal the control's."""
    lines = []
    for seed, (run, control) in enumerate(zip(RUNS, CONTROL, strict=True)):
        mine, theirs = (ANALYSE_111["learner_records"](r, seed) for r in (run, control))
        val = set(read_json(run / "provenance.json")["cross_sensor"][f"seed{seed}"]["units"]["val"])
        for kind in mine:
            same = {u for u in mine[kind] if mine[kind][u] == theirs[kind].get(u)}
            factor = set(mine[kind]) - val
            lines.append(f"  fold {seed} {kind or 'plan '}records: factor units equal {len(same & factor)} "
                         f"of {len(factor)}; validation units equal {len(same & val)} of {len(val)}")
    return "rule 1:\n" + "\n".join(lines)


def paired(method: str) -> str:
    """Rule 2: the held-out RMSE per unit over the control's, force and angle."""
    now, was = rows_by_unit(RUNS, method), rows_by_unit(CONTROL, method)
    cells = [f"{label} x{paired_text([now[u][key] / was[u][key] for u in was])}"
             for label, key in KEYS.items()]
    return f"  {method}: {'; '.join(cells)} over {len(was)} units"


def main() -> None:
    print(learners())
    print("\nrule 2, held-out RMSE against the control, per unit:")
    for m in METHODS:
        print(paired(m))
    print("\nrule 3, the interval target on both sessions' rows:")
    for seed, run in enumerate(RUNS):
        print(ANALYSE_106["factors"](run, seed))
    for m in METHODS:
        print(ANALYSE_108["intervals"](RUNS, m))
        print(ANALYSE_111["verdict"](rows_by_unit(RUNS, m), m))
    print("\nthe control (entry 110's fleet88r_both), for comparison:")
    for m in METHODS:
        print(ANALYSE_108["intervals"](CONTROL, m))


if __name__ == "__main__":
    main()
