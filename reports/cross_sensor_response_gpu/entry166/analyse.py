"""Research log entry 166's reading: the fresh units' references under every fold from three starts. Rule 1:
start 0 equals the one-start reference wherever that kept the learning rate 0.01. Rule 2: the kept reference
over the one-start reference, per (unit, fold). Rule 3: entries 162-163's four-fold figures against the kept
references. Rule 4: entries 159-160's 128 units against them. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry166/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import mean_interval, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
GPU = HERE.parent
E159 = runpy.run_path(str(GPU / "entry159" / "analyse.py"))
E160 = runpy.run_path(str(GPU / "entry160" / "analyse.py"))
E162 = runpy.run_path(str(GPU / "entry162" / "analyse.py"))
E163 = runpy.run_path(str(GPU / "entry163" / "analyse.py"))
swapped = runpy.run_path(str(GPU / "entry165" / "analyse.py"))["swapped"]  # per_unit rows by (unit, fold)
KEYS, ACROSS, USE, FOLDS = E162["KEYS"], E162["ACROSS"], E163["USE"], E162["FOLDS"]
STARTS = (0, 1, 2)
OWN_SLICE = {0: 0, 1: 32, 2: 64, 3: 96}  # fold -> the first of its own 32 fresh units (entries 158-160)
CELLS = [(0, 32), (1, 0), (2, 0), (2, 32), (3, 0), (3, 32), (2, 64), (3, 96)]  # this entry's (fold, slice)
Cell = tuple[str, int]
TEXT = "{:.3f}x [{:.2f}, {:.2f}]".format


def start_rows() -> dict[tuple[str, int, int], dict]:
    """(unit, fold, start) -> its reference row: entry 164's folds 0 and 1 (their own units) and this entry's
    slices, those that have run."""
    at = [GPU / "entry164" / f"other16f_seed{k}" for k in (0, 1)]
    at += [HERE / f"other16f_seed{k}_from{f}" for k, f in CELLS]
    files = [p / "references.json" for p in at if (p / "references.json").is_file()]
    rows = [r for f in files for r in read_json(f)["rows"]]
    return {(r["unit"], r["seed"], r["start"]): r for r in rows}


def one_start() -> dict[Cell, dict]:
    """(unit, fold) -> its one-start reference: entry 159's for a fold's own units, entry 162's otherwise."""
    rows = [r for k in FOLDS for f in (0, 32) for r in E162["fold_rows"](k, f)]
    rows += [r for k in (2, 3) for r in E159["fresh_rows"]() if r["seed"] == k]
    return {(r["unit"], r["seed"]): r for r in rows if r["method"] == "per_unit"}


def kept(starts: dict, cells: list[Cell]) -> dict[Cell, dict]:
    """(unit, fold) -> the start with the lowest validation loss."""
    return {c: min((starts[(*c, j)] for j in STARTS), key=lambda r: r["val_loss"]) for c in cells}


def gate(starts: dict, old: dict, cells: list[Cell]) -> str:
    """Rule 1: start 0 against the one-start reference where that kept 0.01."""
    same_lr = [c for c in cells if old[c]["reference_lr"] == 0.01]
    differ = [c for c in same_lr if any(starts[(*c, 0)][k] != old[c][k] for k in KEYS.values())]
    return (f"{len(same_lr) - len(differ)} of {len(same_lr)} (unit, fold) cells that kept 0.01: start 0's "
            "RMSEs equal the one-start reference's" + (f"; DIFFER: {differ}" if differ else ""))


def four_folds(refs: dict[Cell, dict]) -> None:
    """Rules 2-3 on entry 162's 64 units by four folds."""
    print("\nrule 2, the kept reference over the one-start reference, per (unit, fold), 64 units by 4 folds, "
          "geometric mean [95%, resampling units and folds]")
    old = one_start()
    for name, key in KEYS.items():
        logs = np.log([[refs[u, k][key] / old[u, k][key] for k in FOLDS] for u in E162["UNITS"]])
        m, lo, hi = (float(np.exp(v)) for v in E162["crossed_interval"](logs))
        print(f"{name}: x{m:.3f} [{lo:.3f}, {hi:.3f}]")
    print("\nrule 3, the mean over four folds and 64 units [95%, resampling units and folds]")
    print("| method | against one start | against three starts |")
    print("|---|---|---|")
    runs = (("the plan alone (entry 162)", E163["rows"]("entry158", GPU / "entry162"), ACROSS),
            ("with ordinary use (entry 163)", E163["rows"]("entry160", GPU / "entry163"), USE))
    for label, rows, method in runs:
        got = [" / ".join(TEXT(*E162["crossed_interval"](E162["ratios"](r, method)[n])) for n in KEYS)
               for r in (rows, swapped(rows, refs))]
        print(f"| {label} | {got[0]} | {got[1]} |")


def own_units(refs: dict[Cell, dict]) -> None:
    """Rule 4: entries 159-160's 128 units, each under its own fold, over units."""
    print("\nrule 4, the 128 fresh units under their own folds, mean over units [95%]")
    print("| method | against one start | against three starts |")
    print("|---|---|---|")
    for label, rows, method in (("the plan alone (entry 159)", E159["fresh_rows"](), ACROSS),
                                ("with ordinary use (entry 160)", E160["rows"](), USE)):
        got = [" / ".join(TEXT(*mean_interval(list(unit_ratios(r, key)[method, 120.0].values())))
                          for key in KEYS.values()) for r in (rows, swapped(rows, refs))]
        print(f"| {label} | {got[0]} | {got[1]} |")


def main() -> None:
    starts, old = start_rows(), one_start()
    cells = sorted({(u, k) for u, k, _ in starts})
    refs = kept(starts, cells)
    print(f"rule 1: {gate(starts, old, cells)}")
    if all((u, k) in refs for u in E162["UNITS"] for k in FOLDS):
        four_folds(refs)
    own = {(r["unit"], r["seed"]) for r in E159["fresh_rows"]() if r["method"] == "per_unit"}
    if own <= refs.keys():
        own_units(refs)


if __name__ == "__main__":
    main()
