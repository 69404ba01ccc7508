"""Research log entry 173's reading: fleet88's designed plan at 120 s over a second draw of the start
network. Rule 1: each fold's references and every designed plan equal entry 146's, and the start network
differs from draw 0's. Rule 2: alone and with ordinary use for draw 0 (entry 146), draw 1 and both averaged
per unit, against entry 165's references kept over three starts; draw 1 over draw 0 per unit, by fold. Entry
174 reads its budgets with the same functions. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry173/analyse.py > \\
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
FOLDS = (0, 1)
RUNS = {0: GPU / "entry146" / "at120", 1: HERE / "fleet88_d1"}  # draw -> the runs' root
START = GPU.parent / "cross_sensor_response_start"


def plans(rows: list[dict], budgets: tuple[float, ...]) -> dict[tuple, tuple]:
    """(method, unit, seed, budget) -> (rows, robot seconds) of every designed job at `budgets`."""
    return {(r["method"], r["unit"], r["seed"], r["budget_s"]): (r["calib_samples"], r["calib_seconds"])
            for r in rows if r["method"] in dict(METHODS) and r.get("budget_s") in budgets}


def start_differs(runs: dict[int, Path], k: int) -> bool:
    """Whether draw 1's saved start network differs from the run's (draw 0's)."""
    name = f"models/response_seed{k}_start.safetensors"
    a, b = load_file(f88(runs[1], k) / name), load_file(START / f"fleet88_seed{k}" / name)
    return any(not np.array_equal(a[t], b[t]) for t in a)


def gate(runs: dict[int, Path], budgets: tuple[float, ...]) -> bool:
    ok = True
    for k in FOLDS:
        new, old = metrics(f88(runs[1], k)), metrics(f88(runs[0], k))
        refs = E153["references"](new) == E153["references"](old)
        mine, theirs = plans(new, budgets), plans(old, budgets)
        same = mine == theirs and len(mine) == 2 * 44 * len(budgets)
        differs = start_differs(runs, k)
        ok &= refs and same and differs
        print(f"rule 1, fold {k}: references {'equal' if refs else 'DIFFER'}; {len(mine)} plans "
              f"{'equal' if same else 'DIFFER'}; start network {'differs' if differs else 'SAME'}")
    return ok


def rows_of(runs: dict[int, Path], draws: tuple[int, ...], budgets: tuple[float, ...]) -> list[dict]:
    return [r for d in draws for k in FOLDS for r in metrics(f88(runs[d], k))
            if r["method"] == "per_unit" or (r["method"] in dict(METHODS) and r.get("budget_s") in budgets)]


def cells(runs: dict[int, Path], budgets: tuple[float, ...], base: str) -> None:
    new, _ = E165["new_references"]("fleet88")
    print("\nrule 2, fleet88 (88 units), against three starts: force / angle, mean over units [95%]")
    label0 = f"draw 0 ({base})"
    print(f"| the designed plan | {label0} | draw 1 | both draws | verdict, both |" if len(budgets) > 1 else
          f"| the designed plan at {budgets[0]:g} s | {label0} | draw 1 | both draws | verdict, both |")
    print("|---|---|---|---|---|")
    got = {draws: E165["swapped"](rows_of(runs, draws, budgets), new) for draws in ((0,), (1,), (0, 1))}
    for method, label in METHODS:
        for b in budgets:
            texts = [E165["cell"](got[d], method, b) for d in got]
            verdict = E165["verdict"](texts[-1][1], 1.10)
            name = f"{b:g} s, {label}" if len(budgets) > 1 else label
            print(f"| {name} | " + " | ".join(t for t, _ in texts) + f" | {verdict} |")
    print("\nrule 2, draw 1 over draw 0 per unit, by fold (the same references)")
    for method, _ in METHODS:
        for b in budgets:
            for key in ("force", "angle"):
                parts = []
                for k in FOLDS:
                    one = {d: unit_ratios([r for r in got[(d,)] if r["seed"] == k], KEYS[key])[method, b]
                           for d in (0, 1)}
                    parts.append(f"fold {k} x{paired_text([one[1][u] / one[0][u] for u in sorted(one[0])])}")
                at = f" at {b:g} s" if len(budgets) > 1 else ""
                print(f"  {method}{at}, {key}: " + "; ".join(parts))


def read(runs: dict[int, Path], budgets: tuple[float, ...], base: str) -> None:
    """Rule 1, then rule 2 where it holds."""
    if gate(runs, budgets):
        cells(runs, budgets, base)


if __name__ == "__main__":
    read(RUNS, (120.0,), "entry 146")
