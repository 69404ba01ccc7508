"""Research log entry 173's reading: fleet88's designed plan at 120 s over a second draw of the start
network. Rule 1: each fold's references and every designed plan equal entry 146's, and the start network
differs from draw 0's. Rule 2: alone and with ordinary use for draw 0 (entry 146), draw 1 and both averaged
per unit, against entry 165's references kept over three starts; draw 1 over draw 0 per unit, by fold. Usage,
from the repository root:

    python reports/cross_sensor_response_gpu/entry173/analyse.py > \
        reports/cross_sensor_response_gpu/entry173/logs/analyse.log
"""

import runpy
from pathlib import Path

import numpy as np
from safetensors.numpy import load_file

from anytip.report.cross_sensor import paired_text, unit_ratios

HERE = Path(__file__).parent
GPU = HERE.parent
E153 = runpy.run_path(str(GPU / "entry153" / "analyse.py"))
E165 = runpy.run_path(str(GPU / "entry165" / "analyse.py"))
KEYS, metrics, f88 = E153["KEYS"], E153["metrics"], E153["f88"]
METHODS = ((E165["DESIGNED_USE"], "with ordinary use"), (E165["DESIGNED"], "the plan alone"))
FOLDS, BUDGET = (0, 1), 120.0
RUNS = {0: GPU / "entry146" / "at120", 1: HERE / "fleet88_d1"}
START = GPU.parent / "cross_sensor_response_start"


def plans(rows: list[dict]) -> dict[tuple, tuple]:
    """(method, unit, seed) -> (rows, robot seconds) of every designed job at 120 s."""
    return {(r["method"], r["unit"], r["seed"]): (r["calib_samples"], r["calib_seconds"])
            for r in rows if r["method"] in dict(METHODS) and r.get("budget_s") == BUDGET}


def start_differs(k: int) -> bool:
    """Whether draw 1's saved start network differs from the run's (draw 0's)."""
    name = f"models/response_seed{k}_start.safetensors"
    a, b = load_file(f88(RUNS[1], k) / name), load_file(START / f"fleet88_seed{k}" / name)
    return any(not np.array_equal(a[t], b[t]) for t in a)


def gate() -> bool:
    ok = True
    for k in FOLDS:
        new, old = metrics(f88(RUNS[1], k)), metrics(f88(RUNS[0], k))
        refs = E153["references"](new) == E153["references"](old)
        mine, theirs = plans(new), plans(old)
        same = mine == theirs and len(mine) == 2 * 44
        differs = start_differs(k)
        ok &= refs and same and differs
        print(f"rule 1, fold {k}: references {'equal' if refs else 'DIFFER'}; {len(mine)} plans "
              f"{'equal' if same else 'DIFFER'}; start network {'differs' if differs else 'SAME'}")
    return ok


def rows_of(draws: tuple[int, ...]) -> list[dict]:
    return [r for d in draws for k in FOLDS for r in metrics(f88(RUNS[d], k))
            if r["method"] == "per_unit" or (r["method"] in dict(METHODS) and r.get("budget_s") == BUDGET)]


def cells() -> None:
    new, _ = E165["new_references"]("fleet88")
    print("\nrule 2, fleet88 (88 units), against three starts: force / angle, mean over units [95%]")
    print("| the designed plan at 120 s | draw 0 (entry 146) | draw 1 | both draws | verdict, both |")
    print("|---|---|---|---|---|")
    got = {draws: E165["swapped"](rows_of(draws), new) for draws in ((0,), (1,), (0, 1))}
    for method, label in METHODS:
        texts = [E165["cell"](got[d], method, BUDGET) for d in got]
        verdict = E165["verdict"](texts[-1][1], 1.10)
        print(f"| {label} | " + " | ".join(t for t, _ in texts) + f" | {verdict} |")
    print("\nrule 2, draw 1 over draw 0 per unit, by fold (the same references)")
    for method, _ in METHODS:
        for key in ("force", "angle"):
            parts = []
            for k in FOLDS:
                one = {d: unit_ratios([r for r in got[(d,)] if r["seed"] == k], KEYS[key])[method, BUDGET]
                       for d in (0, 1)}
                parts.append(f"fold {k} x{paired_text([one[1][u] / one[0][u] for u in sorted(one[0])])}")
            print(f"  {method}, {key}: " + "; ".join(parts))


if __name__ == "__main__":
    if gate():
        cells()
