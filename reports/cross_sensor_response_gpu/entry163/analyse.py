"""Research log entry 163's reading: the 64 fresh units SIM25-000 to 063 under each of other16's four folds at
120 s, `cover_informative`, with 600 s of ordinary use, against entry 162's references (entry 159's for a
fold's own units). Rule 1: every (unit, fold) with its row with ordinary use, the plan alone's RMSEs as
entry 162's. Rule 2: each fold's mean over the same 64 units, the variance of log r_use between folds,
units and left over. Rule 3: the mean over folds and units, its interval resampling both, against the goal.
Rule 4: the folds' spread with and without ordinary use, and ordinary use over the plan alone per fold.
Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry163/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text

HERE = Path(__file__).parent
E162 = runpy.run_path(str(HERE.parent / "entry162" / "analyse.py"))
KEYS, ACROSS, FOLDS, UNITS, OWN = E162["KEYS"], E162["ACROSS"], E162["FOLDS"], E162["UNITS"], E162["OWN"]
USE, BUDGET = "response+use@cover_informative", E162["BUDGET"]


def rows(own: str, new: Path) -> list[dict]:
    """Every fold's rows of the 64 units (a fold's own from entry `own`, the rest from `new`), and their
    references."""
    return [r for k in FOLDS for from_ in (0, 32) for r in E162["fold_rows"](k, from_, own, new)]


def same_alone(mine: list[dict], theirs: list[dict]) -> float:
    """Rule 1: the largest relative difference between the plan alone's RMSEs here and in entry 162
    (entry 158's for the own folds)."""
    def cells(got: list[dict]) -> dict[tuple, float]:
        return {(r["unit"], r["seed"], key): r[key] for r in got
                if r["method"] == ACROSS and r.get("budget_s") == BUDGET for key in KEYS.values()}
    a, b = cells(mine), cells(theirs)
    if a.keys() != b.keys():
        return float("inf")
    return max(abs(a[c] / b[c] - 1) for c in a)


def main() -> None:
    got, alone_rows = rows("entry160", HERE), rows("entry158", HERE.parent / "entry162")
    missing, most = E162["gate"](got, USE), same_alone(got, alone_rows)
    print(f"rule 1: {len(UNITS) * len(FOLDS) - len(missing)} of {len(UNITS) * len(FOLDS)} (unit, fold) cells "
          f"with a row with ordinary use and a reference on as many test rows"
          + (f"; MISSING {missing}" if missing else "")
          + f"; the plan alone's RMSEs differ from entry 162's by at most {most:.1e} of their value")
    if missing or most > 1e-6:
        return
    use, alone = E162["ratios"](got, USE), E162["ratios"](alone_rows)
    text = "{:.3f}x [{:.2f}, {:.2f}]".format
    print("\nrule 2, with ordinary use, RMSE over the unit's own reference under the fold, mean over the "
          "same 64 units [95% interval]")
    print("| fold | force | angle | force, the plan alone (entry 162) |")
    print("|---|---|---|---|")
    for k in FOLDS:
        cells = [text(*mean_interval(list(use[n][:, k]))) for n in KEYS]
        print(f"| {k} | " + " | ".join(cells) + f" | {text(*mean_interval(list(alone['force'][:, k])))} |")
    for name in KEYS:
        for label, r in (("with ordinary use", use), ("the plan alone", alone)):
            shares = ", ".join(f"{part} {v:.0%}" for part, v in E162["variance_shares"](r[name]).items())
            print(f"{name}, {label}: variance of log r between {shares}")
    print("\nrule 3, the mean over four folds and 64 units, with ordinary use")
    for name in KEYS:
        print(f"{name}: {text(*E162['crossed_interval'](use[name]))} resampling units and folds; "
              f"t over the four fold means {text(*E162['t_interval'](use[name].mean(0)))}")
    print("\nrule 4, the folds' spread: the standard deviation of the four folds' mean log r on the same "
          "units")
    for name in KEYS:
        sd = {label: np.log(r[name]).mean(0).std(ddof=1) for label, r in (("use", use), ("alone", alone))}
        print(f"{name}: with ordinary use {sd['use']:.4f}, the plan alone {sd['alone']:.4f} "
              f"(ratio {sd['use'] / sd['alone']:.2f})")
    for k in FOLDS:
        per = {n: paired_text(list(use[n][:, k] / alone[n][:, k])) for n in KEYS}
        print(f"fold {k}: ordinary use over the plan alone, per unit, force x{per['force']}, "
              f"angle x{per['angle']}")
    E162["exploratory"](got, USE)


if __name__ == "__main__":
    main()
