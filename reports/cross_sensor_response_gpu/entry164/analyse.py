"""Research log entry 164's reading: the references of folds 0 and 1's fresh units from three starts. Rule 1:
start 0 equals entry 159's reference wherever that kept the learning rate 0.01. Rule 2: the spread over
starts per unit against entry 162's spread between folds; how often the validation loss picks the best test
start. Rule 3: the reference kept over three starts by its validation loss, over entry 159's, per unit.
Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry164/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
E159 = runpy.run_path(str(HERE.parent / "entry159" / "analyse.py"))
E162 = runpy.run_path(str(HERE.parent / "entry162" / "analyse.py"))
KEYS, ACROSS, FOLDS, STARTS = E159["KEYS"], E159["ACROSS"], (0, 1), (0, 1, 2)


def starts() -> dict[tuple[str, int], dict]:
    """(unit, start) -> its reference row, folds 0 and 1."""
    rows = [r for k in FOLDS for r in read_json(HERE / f"other16f_seed{k}" / "references.json")["rows"]]
    return {(r["unit"], r["start"]): r for r in rows}


def before() -> dict[str, dict]:
    """unit -> entry 159's reference row, folds 0 and 1."""
    at = HERE.parent / "entry159"
    rows = [r for k in FOLDS for r in read_json(at / f"other16f_seed{k}" / "references.json")["rows"]]
    return {r["unit"]: r for r in rows}


def gate(got: dict, old: dict) -> str:
    """Rule 1: start 0 against entry 159 where that kept 0.01."""
    kept = [u for u, r in old.items() if r["reference_lr"] == 0.01]
    differ = [u for u in kept if any(got[u, 0][k] != old[u][k] for k in KEYS.values())]
    same = f"{len(kept) - len(differ)} of {len(kept)} units that kept 0.01: start 0's RMSEs equal entry 159's"
    return same + (f"; DIFFER: {differ}" if differ else "")


def kept(got: dict, units: list[str], starts: tuple[int, ...] | range = STARTS) -> dict[str, dict]:
    """unit -> the start of `starts` with the lowest validation loss."""
    return {u: min((got[u, j] for j in starts), key=lambda r: r["val_loss"]) for u in units}


def main() -> None:
    got, old = starts(), before()
    units = sorted(old)
    print(f"rule 1: {gate(got, old)}")
    force = KEYS["force"]
    logs = np.log([[got[u, j][force] for j in STARTS] for u in units])
    rows162 = [r for k in E162["FOLDS"] for f in (0, 32) for r in E162["fold_rows"](k, f)]
    between = E162["left_over"](E162["log_rmse"](rows162, "per_unit", force))
    spread, square = np.exp(logs.std(1, ddof=1).mean()) - 1, logs.var(1, ddof=1).mean()
    print(f"\nrule 2: over three starts a unit's reference spreads by {spread:.1%} (mean sd of log force "
          f"RMSE); mean square {square:.4f} against {between:.4f} between folds (entry 162)")
    best_test = {u: int(np.argmin(logs[i])) for i, u in enumerate(units)}
    chosen = kept(got, units)
    same = sum(chosen[u]["start"] == best_test[u] for u in units)
    print(f"the validation loss picks the best test start for {same} of {len(units)} units")
    print("\nrule 3: the reference kept over three starts, over entry 159's, per unit")
    for name, key in KEYS.items():
        print(f"{name}: x{paired_text([chosen[u][key] / old[u][key] for u in units])}")
    text = "{:.3f}x [{:.2f}, {:.2f}]".format
    fresh = [r for r in E159["fresh_rows"]() if r["unit"] in old and r["method"] != "per_unit"]
    for label, refs_now in (("entry 159's", old), ("kept over three starts", chosen)):
        rows = fresh + [{**r, "method": "per_unit"} for r in refs_now.values()]
        cells = [text(*mean_interval(list(unit_ratios(rows, k)[ACROSS, 120.0].values())))
                 for k in KEYS.values()]
        print(f"`cover_informative` at 120 s against {label} references: " + " / ".join(cells))


if __name__ == "__main__":
    main()
