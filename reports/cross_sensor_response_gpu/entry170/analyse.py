"""Research log entry 170's reading: the other elastomer's 64 fresh units under four folds over a second draw
of the start network. Rule 1: each job's plans equal draw 0's (entries 160 and 163) and its rows are scored on
their references' test rows. Rule 2: draw 1 and the two draws averaged, against entry 166's references kept
over three starts, over units and folds; draw 1 over draw 0 per (unit, fold), by fold. Usage, from the
repository root:

    python reports/cross_sensor_response_gpu/entry170/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import paired_text
from anytip.rundir import read_json

HERE = Path(__file__).parent
GPU = HERE.parent
E162 = runpy.run_path(str(GPU / "entry162" / "analyse.py"))
E163 = runpy.run_path(str(GPU / "entry163" / "analyse.py"))
E166 = runpy.run_path(str(GPU / "entry166" / "analyse.py"))
E169 = runpy.run_path(str(GPU / "entry169" / "analyse.py"))
swapped, plans = E169["E165"]["swapped"], E169["plans"]  # plans by (method, unit, fold, budget)
KEYS, ACROSS, USE, FOLDS, UNITS = E162["KEYS"], E162["ACROSS"], E163["USE"], E162["FOLDS"], E162["UNITS"]
TEXT = "{:.3f}x [{:.2f}, {:.2f}]".format


def draw1() -> list[dict]:
    """This entry's rows of the 64 units, each with its fold as its seed."""
    rows = []
    for k in FOLDS:
        for from_ in (0, 32):
            got = read_json(HERE / f"other16f_seed{k}_from{from_}" / "rows.json")
            rows += [{**r, "seed": got["seed"]} for r in got["rows"] if r["unit"] in UNITS]
    return rows


def main() -> None:
    zero, new = E163["rows"]("entry160", GPU / "entry163"), draw1()
    refs0 = [r for r in zero if r["method"] == "per_unit"]
    mine, theirs = plans(new), plans(zero)
    missing = {m: E162["gate"](refs0 + new, m) for m in (ACROSS, USE)}
    print(f"rule 1: {len(mine)} plans, {'equal' if mine == theirs else 'DIFFER'} to draw 0's; cells not "
          f"scored on their reference's test rows: {sum(map(len, missing.values()))}")
    starts = E166["start_rows"]()
    kept = E166["kept"](starts, sorted({(u, k) for u, k, _ in starts}))
    both = {"draw 0": swapped(zero, kept), "draw 1": swapped(refs0 + new, kept),
            "both draws": swapped(zero + new, kept)}
    print("\nrule 2, 64 units by four folds against three starts: force / angle, mean [95%, resampling units "
          "and folds]")
    print("| method | " + " | ".join(both) + " |")
    print("|---|---|---|---|")
    got = {label: {m: E162["ratios"](rows, m) for m in (USE, ACROSS)} for label, rows in both.items()}
    for method, label in ((USE, "with ordinary use"), (ACROSS, "the plan alone")):
        cells = [" / ".join(TEXT(*E162["crossed_interval"](got[d][method][n])) for n in KEYS) for d in both]
        print(f"| {label} | " + " | ".join(cells) + " |")
    print("\nrule 2, draw 1 over draw 0 per (unit, fold), force, by fold")
    for method in (USE, ACROSS):
        r = got["draw 1"][method]["force"] / got["draw 0"][method]["force"]
        print(f"  {method}: " + "; ".join(f"fold {k} x{paired_text(list(r[:, k]))}" for k in FOLDS)
              + f"; all x{np.exp(np.log(r).mean()):.3f}")


if __name__ == "__main__":
    main()
