"""Research log entry 155's reading: today's recipe on fleet88 at 30 and 120 s, the plan alone, with each of
its four steps taken out in turn. Rule 1: each run's references equal entry 153's, every plan within its
budget, and the `all` arm's `cover_informative` rows against entry 153's. Rule 2: l_b(s), the arm without step
s over `all` per unit, and l_30(s) / l_120(s). Rule 3: the product of the four l_30 against entry 153's
1/g(30). Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry155/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import paired_interval, paired_text

HERE = Path(__file__).parent
GPU = HERE.parent
E153 = runpy.run_path(str(GPU / "entry153" / "analyse.py"))
metrics, checked, f88, KEYS = E153["metrics"], E153["checked"], E153["f88"], E153["KEYS"]
FOLDS, BUDGETS = (0, 1), (30.0, 120.0)
ALL = "response@cover_informative"
# step -> (arm directory, method in it): each arm is today's recipe without that step
STEPS = {"the exchange (`cover`)": ("all", "response@cover"), "the registry code prior": ("prior", ALL),
         "the converged code fit": ("fit", ALL), "the residual correction": ("residual", ALL)}


def rmses(arm: str, method: str, budget: float, key: str) -> dict[str, float]:
    """unit -> the arm's RMSE of `key` for `method` at `budget`, over both folds."""
    return {r["unit"]: r[key] for k in FOLDS for r in metrics(f88(HERE / arm, k))
            if r["method"] == method and r.get("budget_s") == budget}


def same_rows(k: int) -> str:
    """Rule 1's last part: the `all` arm's `cover_informative` RMSEs at 30 and 120 s against entry 153's."""
    def cells(run: Path) -> dict[tuple, float]:
        return {(r["unit"], r["budget_s"], key): r[key] for r in metrics(run)
                if r["method"] == ALL and r.get("budget_s") in BUDGETS for key in KEYS.values()}
    mine, theirs = cells(f88(HERE / "all", k)), cells(f88(GPU / "entry153", k))
    if mine == theirs:
        return f"{len(mine)} RMSEs equal entry 153's"
    shared = sorted(set(mine) & set(theirs))
    most = max(abs(mine[s] / theirs[s] - 1) for s in shared)
    return f"{len(shared)} shared RMSEs DIFFER from entry 153's, the most by {most:.2e}"


def ratios(step: str, budget: float, key: str) -> dict[str, float]:
    """unit -> the arm without `step` over `all`, at `budget`."""
    arm, method = STEPS[step]
    out, base = rmses(arm, method, budget, key), rmses("all", ALL, budget, key)
    return {u: out[u] / base[u] for u in base}


def main() -> None:
    for arm in ("all", "prior", "fit", "residual"):
        for k in FOLDS:
            methods = (ALL, "response@cover") if arm == "all" else (ALL,)
            print(f"rule 1, {arm} fold {k}: {checked(f88(HERE / arm, k), f88(GPU / 'entry153', k), methods)}")
    for k in FOLDS:
        print(f"rule 1, all fold {k}: {same_rows(k)}")
    print("\nrule 2, fleet88 (88 units), the plan alone: each step taken out, over today's recipe, per unit")
    print("| step taken out | force, 30 s | force, 120 s | l_30 / l_120, force | angle, 30 s | "
          "angle, 120 s |\n|---|---|---|---|---|---|")
    product: dict[float, np.ndarray] = {b: np.ones(1) for b in BUDGETS}
    for step in STEPS:
        f = {b: ratios(step, b, KEYS["force"]) for b in BUDGETS}
        a = {b: ratios(step, b, KEYS["angle"]) for b in BUDGETS}
        units = sorted(f[30.0])
        growth = [f[30.0][u] / f[120.0][u] for u in units]
        mark = " (carries growth)" if paired_interval(growth)[1] > 1.03 else ""
        cells = [paired_text([f[b][u] for u in units]) for b in BUDGETS] + [paired_text(growth) + mark]
        cells += [paired_text([a[b][u] for u in units]) for b in BUDGETS]
        print(f"| {step} | " + " | ".join(f"x{c}" for c in cells) + " |")
        for b in BUDGETS:
            product[b] = product[b] * np.array([f[b][u] for u in units])
    for b in BUDGETS:
        print(f"rule 3: the product of the four, {b:g} s, force: x{paired_text(list(product[b]))}")
    print("entry 153: 1/g(30) = x1.342, 1/g(120) = x1.107 (today's recipe over entry 26's, per unit)")


if __name__ == "__main__":
    main()
