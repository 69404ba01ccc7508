"""Research log entry 169's reading: fleet88 at 30, 60 and 120 s over a second draw of the start network.
Rule 1: each fold's references and every job's plan equal entry 153's, and the start network differs from
draw 0's. Rule 2: each cell for draw 0 (entry 153), draw 1 and both averaged per unit, against entry 165's
references kept over three starts; draw 1 over draw 0 per unit, by fold. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry169/analyse.py
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
KEYS, ALONE, USE, metrics, f88 = E153["KEYS"], E153["ALONE"], E153["USE"], E153["metrics"], E153["f88"]
FOLDS, BUDGETS = (0, 1), (30.0, 60.0, 120.0)
START = GPU.parent / "cross_sensor_response_start"


def plans(rows: list[dict]) -> dict[tuple, tuple]:
    """(method, unit, seed, budget) -> (rows, robot seconds) of every job at the entry's budgets."""
    return {(r["method"], r["unit"], r["seed"], r["budget_s"]): (r["calib_samples"], r["calib_seconds"])
            for r in rows if r["method"] in (ALONE, USE) and r.get("budget_s") in BUDGETS}


def start_differs(k: int) -> bool:
    """Whether draw 1's saved start network differs from the run's (draw 0's)."""
    name = f"models/response_seed{k}_start.safetensors"
    a = load_file(HERE / "fleet88_d1" / f"fleet88_seed{k}" / name)
    b = load_file(START / f"fleet88_seed{k}" / name)
    return any(not np.array_equal(a[t], b[t]) for t in a)


def gate() -> None:
    for k in FOLDS:
        new, old = metrics(f88(HERE / "fleet88_d1", k)), metrics(f88(GPU / "entry153", k))
        refs = E153["references"](new) == E153["references"](old)
        mine, theirs = plans(new), plans(old)
        same = mine == {c: theirs[c] for c in mine} and len(mine) == 2 * 3 * 44
        print(f"rule 1, fold {k}: references {'equal' if refs else 'DIFFER'}; {len(mine)} plans "
              f"{'equal' if same else 'DIFFER'}; start network {'differs' if start_differs(k) else 'SAME'}")


def rows_of(draws: tuple[int, ...]) -> list[dict]:
    runs = {0: GPU / "entry153", 1: HERE / "fleet88_d1"}
    return [r for d in draws for k in FOLDS for r in metrics(f88(runs[d], k))
            if r["method"] == "per_unit" or (r["method"] in (ALONE, USE) and r.get("budget_s") in BUDGETS)]


def cells() -> None:
    new, _ = E165["new_references"]("fleet88")
    print("\nrule 2, fleet88 (88 units), against three starts: force / angle, mean over units [95%]")
    print("| cell | draw 0 (entry 153) | draw 1 | both draws | verdict, both |")
    print("|---|---|---|---|---|")
    got = {draws: E165["swapped"](rows_of(draws), new) for draws in ((0,), (1,), (0, 1))}
    for method, label in ((USE, "with ordinary use"), (ALONE, "the plan alone")):
        for b in BUDGETS:
            texts = [E165["cell"](got[d], method, b) for d in got]
            print(f"| {b:g} s, {label} | " + " | ".join(t for t, _ in texts)
                  + f" | {E165['verdict'](texts[-1][1], 1.10)} |")
    print("\nrule 2, draw 1 over draw 0 per unit, by fold (the same references)")
    for method in (USE, ALONE):
        for b in BUDGETS:
            parts = []
            for k in FOLDS:
                one = {d: unit_ratios([r for r in got[(d,)] if r["seed"] == k], KEYS["force"])[method, b]
                       for d in (0, 1)}
                parts.append(f"fold {k} x{paired_text([one[1][u] / one[0][u] for u in sorted(one[0])])}")
            print(f"  {method} at {b:g} s, force: " + "; ".join(parts))


if __name__ == "__main__":
    gate()
    cells()
