"""Research log entry 159's reading: entry 158's rows of 128 fresh units of the other elastomer against their
per-unit references. Rule 1: each reference scored on as many test rows as entry 158's rows of its unit. Rule
2: per unit RMSE over its reference's, mean over units [95% bootstrap interval], `cover_informative` and
`cover` at 30 and 120 s; other16's 16 units in start draw 0 beside (entries 153 and 157). Rule 3: the 120 s
goal on the fresh units. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry159/analyse.py
"""

import runpy
from pathlib import Path

from anytip.report.cross_sensor import mean_interval, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
E157 = runpy.run_path(str(HERE.parent / "entry157" / "analyse.py"))
E158 = runpy.run_path(str(HERE.parent / "entry158" / "analyse.py"))
KEYS, BUDGETS, ACROSS, COVER = E157["KEYS"], E157["BUDGETS"], E157["ACROSS"], E157["COVER"]
E153 = HERE.parent / "entry153"


def fresh_rows() -> list[dict]:
    """Entry 158's rows with their fold's seed, and every fold's references."""
    rows = []
    for k in E158["FOLDS"]:
        got = read_json(HERE.parent / "entry158" / f"other16f_seed{k}" / "rows.json")
        rows += [{**r, "seed": got["seed"]} for r in got["rows"]]
        rows += read_json(HERE / f"other16f_seed{k}" / "references.json")["rows"]
    return rows


def gate(rows: list[dict]) -> str:
    """Rule 1: each reference's test rows against entry 158's rows of its unit."""
    tested = {r["unit"]: r["test_rows"] for r in rows if r["method"] == "per_unit"}
    differ = {r["unit"] for r in rows
              if r["method"] != "per_unit" and r["interval_test_rows"] != tested[r["unit"]]}
    if differ:
        return f"{len(tested)} references; test rows DIFFER for {sorted(differ)}"
    return f"{len(tested)} references; every unit's test rows as many as entry 158's"


def draw0_rows() -> list[dict]:
    """other16's 16 units in start draw 0: `cover_informative` from entry 153, `cover` from entry 157."""
    rows = []
    for k in E157["FOLDS"]:
        base, cover = E157["o16"](E153, 0, k), E157["o16"](HERE.parent / "entry157", 0, k)
        rows += [r for r in E157["metrics"](base) if r["method"] in ("per_unit", ACROSS)]
        rows += [r for r in E157["metrics"](cover) if r["method"] == COVER]
    return [r for r in rows if r["method"] == "per_unit" or r.get("budget_s") in BUDGETS]


def cells(rows: list[dict]) -> dict[tuple[str, float, str], tuple[float, float, float]]:
    """(method, budget, target) -> mean ratio over units [95% interval]."""
    out = {}
    for name, key in KEYS.items():
        for (method, budget), by_unit in unit_ratios(rows, key).items():
            out[method, budget, name] = mean_interval(list(by_unit.values()))
    return out


def main() -> None:
    rows = fresh_rows()
    print(f"rule 1: {gate(rows)}")
    fresh, other16 = cells(rows), cells(draw0_rows())
    print("\nrule 2, RMSE over the unit's own per-unit reference, mean over units [95% interval], "
          "force / angle")
    print("| plan | budget | 128 fresh units (SIM25-*) | other16's 16 units, start draw 0 |")
    print("|---|---|---|---|")
    text = "{:.3f}x [{:.2f}, {:.2f}]".format
    for method in (ACROSS, COVER):
        for b in BUDGETS:
            row = [" / ".join(text(*got[method, b, n]) for n in KEYS) for got in (fresh, other16)]
            print(f"| {method} | {b:g} s | " + " | ".join(row) + " |")
    met = all(fresh[ACROSS, 120.0, n][0] <= 1.10 and fresh[ACROSS, 120.0, n][2] <= 1.25 for n in KEYS)
    print(f"\nrule 3: the 120 s goal on the fresh units, `cover_informative`: {'met' if met else 'missed'}")


if __name__ == "__main__":
    main()
