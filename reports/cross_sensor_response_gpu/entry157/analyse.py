"""Research log entry 157's reading: on other16 (16 units, four folds, three start draws), `cover` beside
`cover_informative` with today's recipe at 30 and 120 s, the plan alone. Rule 1: the references equal entry
153's, every plan within its budget, `cover_informative`'s RMSEs against entry 153's. Rule 2: the exchange
taken out, per unit (draws averaged first), l_30, l_120 and l_30 / l_120. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry157/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import paired_text

HERE = Path(__file__).parent
E153 = runpy.run_path(str(HERE.parent / "entry153" / "analyse.py"))
metrics, checked, o16, KEYS = E153["metrics"], E153["checked"], E153["o16"], E153["KEYS"]
DRAWS, FOLDS, BUDGETS = E153["DRAWS"], E153["O16_FOLDS"], (30.0, 120.0)
ACROSS, COVER = "response@cover_informative", "response@cover"


def same_rows(d: int, k: int) -> str:
    """`cover_informative`'s RMSEs at 30 and 120 s against entry 153's run of the same fold and draw."""
    def cells(run: Path) -> dict[tuple, float]:
        return {(r["unit"], r["budget_s"], key): r[key] for r in metrics(run)
                if r["method"] == ACROSS and r.get("budget_s") in BUDGETS for key in KEYS.values()}
    mine, theirs = cells(o16(HERE, d, k)), cells(o16(HERE.parent / "entry153", d, k))
    if mine == theirs:
        return f"{len(mine)} RMSEs equal entry 153's"
    most = max(abs(mine[s] / theirs[s] - 1) for s in set(mine) & set(theirs))
    return f"RMSEs DIFFER from entry 153's, the most by {most:.2e}"


def mean_rmse(method: str, budget: float, key: str) -> dict[str, float]:
    """unit -> its RMSE of `key` averaged over the three draws."""
    acc: dict[str, list[float]] = {}
    for d in DRAWS:
        for k in FOLDS:
            for r in metrics(o16(HERE, d, k)):
                if r["method"] == method and r.get("budget_s") == budget:
                    acc.setdefault(r["unit"], []).append(r[key])
    return {u: float(np.mean(v)) for u, v in acc.items()}


def main() -> None:
    for d in DRAWS:
        for k in FOLDS:
            gate = checked(o16(HERE, d, k), o16(HERE.parent / "entry153", d, k), (ACROSS, COVER))
            print(f"rule 1, draw {d} fold {k}: {gate}; {same_rows(d, k)}")
    print("\nrule 2, other16 (16 units, draws averaged), the plan alone: the exchange taken out "
          "(`cover` over `cover_informative`), per unit")
    print("| target | 30 s | 120 s | 30 s over 120 s |\n|---|---|---|---|")
    for name, key in KEYS.items():
        l_b = {}
        for b in BUDGETS:
            cover, across = mean_rmse(COVER, b, key), mean_rmse(ACROSS, b, key)
            l_b[b] = {u: cover[u] / across[u] for u in sorted(across)}
        units = sorted(l_b[30.0])
        cells = [paired_text([l_b[b][u] for u in units]) for b in BUDGETS]
        cells.append(paired_text([l_b[30.0][u] / l_b[120.0][u] for u in units]))
        print(f"| {name} | " + " | ".join(f"x{c}" for c in cells) + " |")


if __name__ == "__main__":
    main()
