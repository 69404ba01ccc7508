"""Research log entry 104: the 90% intervals of fleet88's CPU rescoring (`cover_informative`, 120 s alone,
24 factor units) with the plan's residual correction on and off. Prints rule 1 (the on arm's held-out errors
against entry 101's), each arm's interval table (`scripts/fold_table.py`: the factor alone and times its
leave-one-out margin), each fold's factors and margins, the unit-outputs below 0.80 by name, and the two
arms paired per unit. From the repository root:

    python reports/cross_sensor_response_gpu/entry104/analyse.py
"""

from __future__ import annotations

import runpy
from pathlib import Path
from typing import Any

import numpy as np

from anytip.rundir import read_json

G = Path("reports/cross_sensor_response_gpu")
ARMS = {arm: [G / f"entry104/fleet88_cpu_{arm}/fleet88_seed{k}" for k in (0, 1)] for arm in ("on", "off")}
CONTROL = [G / f"entry101/fleet88_cpu/fleet88_seed{k}" for k in (0, 1)]
METHOD = "response@cover_informative"
OUTPUTS = ("fx", "fy", "fz", "theta", "phi")
FOLD_TABLE = runpy.run_path("scripts/fold_table.py")  # its functions, not its command line


def held_out(runs: list[Path]) -> dict[str, dict[str, Any]]:
    """The runs' `METHOD` rows at 120 s by unit."""
    return {r["unit"]: r for r in FOLD_TABLE["rows_of"](runs) if r["method"] == METHOD}


def rule_1() -> str:
    """The on arm's held-out force and angle RMSE against entry 101's, unit by unit."""
    mine, theirs = held_out(ARMS["on"]), held_out(CONTROL)
    if set(mine) != set(theirs):
        return f"rule 1: the held-out units differ ({len(mine)} against {len(theirs)})"
    lines = []
    for key in ("force_rmse_n", "angle_rmse_rad"):
        a = np.array([mine[u][key] for u in sorted(mine)])
        b = np.array([theirs[u][key] for u in sorted(mine)])
        lines.append(f"  {key}: {int(np.sum(a == b))} of {len(a)} units equal; largest relative difference "
                     f"{np.max(np.abs(a / b - 1)):.2e}")
    return "rule 1 (on arm against entry 101):\n" + "\n".join(lines)


def factors(run: Path, seed: int) -> str:
    """A fold's fleet factors and leave-one-out margin, as its response model recorded them."""
    rec = read_json(run / f"models/response_seed{seed}.json")
    intervals = rec.get("meta", rec)["intervals"]
    factor = intervals["fleet_factor_by_strategy"]["cover_informative"]["120"]
    margin = intervals["margin_by_strategy"]["cover_informative"]["120"]
    cells = ", ".join(f"{o} {factor[o]:.2f}" for o in OUTPUTS)
    return (f"  fold {seed}: {intervals['factor_units']} factor units; factor {cells}; "
            f"margin {margin['margin']:g} (left-out below 0.80 at 1.00: {margin['below_floor']['1']})")


def below(rows: dict[str, dict[str, Any]], kind: str) -> list[str]:
    """The unit-outputs whose `kind` interval covers less than 0.80 of their test rows."""
    return [f"{u} {o} {r[f'{o}_{kind}_coverage']:.3f}" for u, r in sorted(rows.items()) for o in OUTPUTS
            if r[f"{o}_{kind}_coverage"] < 0.80]


def main() -> None:
    print(rule_1())
    for arm, runs in ARMS.items():
        rows = FOLD_TABLE["rows_of"](runs)
        print(f"\ncorrection {arm}:")
        for seed, run in enumerate(runs):
            print(factors(run, seed))
        for kind in ("fleet", "margin"):
            print(f"\n{kind} intervals:\n{FOLD_TABLE['table'](rows, kind)}")
            print(f"below 0.80: {', '.join(below(held_out(runs), kind)) or 'none'}")
    print("\non against off, per unit:")
    print(FOLD_TABLE["paired"](FOLD_TABLE["rows_of"](ARMS["on"]), FOLD_TABLE["rows_of"](ARMS["off"])))


if __name__ == "__main__":
    main()
