"""Research log entry 158's reading: 128 fresh units of the other elastomer (SIM25-*, 32 under each of
other16's four folds, start draw 0), `cover` beside `cover_informative` with today's recipe at 30 and 120 s,
the plan alone. Rule 1: every plan within its budget, each fresh unit scored under both plans at both budgets.
Rule 2: the exchange taken out, per unit, l_30, l_120 and l_30 / l_120; entry 157's 16 units beside. Usage,
from the repository root:

    python reports/cross_sensor_response_gpu/entry158/analyse.py
"""

import runpy
from pathlib import Path

from anytip.report.cross_sensor import paired_text
from anytip.rundir import read_json

HERE = Path(__file__).parent
E157 = runpy.run_path(str(HERE.parent / "entry157" / "analyse.py"))
KEYS, BUDGETS, ACROSS, COVER = E157["KEYS"], E157["BUDGETS"], E157["ACROSS"], E157["COVER"]
FOLDS, PER_FOLD = range(4), 32


def rows() -> list[dict]:
    """Every fold's held-out rows, fresh units only."""
    got = []
    for k in FOLDS:
        got += read_json(HERE / f"other16f_seed{k}" / "rows.json")["rows"]
    return got


def gate(got: list[dict]) -> str:
    """Rule 1: budgets honoured and every fresh unit scored under both plans at both budgets."""
    over = [r for r in got if r.get("budget_s") and r["calib_seconds"] > r["budget_s"] + 1e-9]
    cells = {(r["unit"], r["method"], r.get("budget_s")) for r in got if r["method"] in (ACROSS, COVER)}
    units = {r["unit"] for r in got}
    full = len(units) == PER_FOLD * len(FOLDS) and len(cells) == len(units) * 2 * len(BUDGETS)
    return (f"{len(units)} fresh units, {len(over)} plans over budget, "
            f"{'every unit under both plans at both budgets' if full else 'CELLS MISSING'}")


def ratios(got: list[dict], key: str) -> dict[float, dict[str, float]]:
    """budget -> unit -> `cover`'s RMSE of `key` over `cover_informative`'s."""
    cell = {(r["unit"], r["method"], r.get("budget_s")): r[key] for r in got}
    units = sorted({r["unit"] for r in got})
    return {b: {u: cell[u, COVER, b] / cell[u, ACROSS, b] for u in units} for b in BUDGETS}


def table(l_b: dict[float, dict[str, float]]) -> list[str]:
    """l_30, l_120 and l_30 / l_120, each as paired text over units."""
    units = sorted(l_b[30.0])
    cells = [paired_text([l_b[b][u] for u in units]) for b in BUDGETS]
    cells.append(paired_text([l_b[30.0][u] / l_b[120.0][u] for u in units]))
    return [f"x{c}" for c in cells]


def main() -> None:
    got = rows()
    print(f"rule 1: {gate(got)}")
    print("\nrule 2, the exchange taken out (`cover` over `cover_informative`), per unit, the plan alone")
    print("| units | target | 30 s | 120 s | 30 s over 120 s | units gaining at 30 s, 120 s |")
    print("|---|---|---|---|---|---|")
    for name, key in KEYS.items():
        l_b = ratios(got, key)
        gains = ", ".join(str(sum(v > 1 for v in l_b[b].values())) for b in BUDGETS)
        print(f"| 128 fresh (SIM25-*) | {name} | " + " | ".join(table(l_b)) + f" | {gains} of 128 |")
    for name, key in KEYS.items():
        l_b = {}
        for b in BUDGETS:
            cover = E157["mean_rmse"](COVER, b, key)
            l_b[b] = {u: cover[u] / a for u, a in E157["mean_rmse"](ACROSS, b, key).items()}
        print(f"| other16's 16 (entry 157, draws averaged) | {name} | " + " | ".join(table(l_b)) + " | |")


if __name__ == "__main__":
    main()
