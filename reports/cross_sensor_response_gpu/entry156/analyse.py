"""Research log entry 156's reading: `cover_informative` with its cells kept to one force level, fleet88 at 30
and 120 s, the plan alone, against entry 155's `all` arm (`cover` and `cover_informative` in one run). Rule 1:
the references equal entry 155's and every plan within its budget. Rule 2: r_b, within one level over across
levels per unit, and the share of the exchange's gain kept. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry156/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import paired_interval, paired_text

HERE = Path(__file__).parent
E155 = runpy.run_path(str(HERE.parent / "entry155" / "analyse.py"))
metrics, checked, f88, KEYS = E155["metrics"], E155["checked"], E155["f88"], E155["KEYS"]
rmses, FOLDS, BUDGETS, ACROSS = E155["rmses"], E155["FOLDS"], E155["BUDGETS"], E155["ALL"]
ALL = E155["HERE"] / "all"


def within(budget: float, key: str) -> dict[str, float]:
    """unit -> the level-kept cells' RMSE of `key` at `budget`, over both folds."""
    return {r["unit"]: r[key] for k in FOLDS for r in metrics(f88(HERE, k))
            if r["method"] == ACROSS and r.get("budget_s") == budget}


def main() -> None:
    for k in FOLDS:
        print(f"rule 1, fold {k}, against entry 155's: {checked(f88(HERE, k), f88(ALL, k), (ACROSS,))}")
    print("\nrule 2, fleet88 (88 units), the plan alone, per unit: within one level over across levels "
          "(r_b), and the share of the exchange's gain kept")
    print("| budget | force r_b | kept, force | angle r_b | kept, angle |\n|---|---|---|---|---|")
    for b in BUDGETS:
        cells = []
        for key in KEYS.values():
            mine, across = within(b, key), rmses("all", ACROSS, b, key)
            cover = rmses("all", "response@cover", b, key)
            units = sorted(across)
            r = [mine[u] / across[u] for u in units]
            gain = paired_interval([cover[u] / across[u] for u in units])[0]
            kept = paired_interval([cover[u] / mine[u] for u in units])[0]
            cells += [f"x{paired_text(r)}", f"{np.log(kept) / np.log(gain):.2f}"]
        print(f"| {b:g} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
