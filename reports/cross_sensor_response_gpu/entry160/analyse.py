"""Research log entry 160's reading: the 128 fresh units of the other elastomer at 120 s with and without 600
s of ordinary use, against entry 159's references. Rule 1: the plan alone's rows equal entry 158's, and every
unit has its row with ordinary use. Rule 2: per unit RMSE over its reference's, mean over units [95%
interval], with and without ordinary use, and with over without per unit; other16's 16 units in start draw 0
beside (entry 153). Rule 3: the 120 s goal with ordinary use on the fresh units. Usage, from the repository
root:

    python reports/cross_sensor_response_gpu/entry160/analyse.py
"""

import runpy
from pathlib import Path

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
E159 = runpy.run_path(str(HERE.parent / "entry159" / "analyse.py"))
E157 = E159["E157"]
KEYS, ACROSS = E159["KEYS"], E159["ACROSS"]
USE = "response+use@cover_informative"


def rows() -> list[dict]:
    """This entry's rows with their fold's seed, and entry 159's references."""
    got = []
    for k in range(4):
        run = read_json(HERE / f"other16f_seed{k}" / "rows.json")
        got += [{**r, "seed": run["seed"]} for r in run["rows"]]
        got += read_json(HERE.parent / "entry159" / f"other16f_seed{k}" / "references.json")["rows"]
    return got


def gate(got: list[dict]) -> str:
    """Rule 1: the plan alone's RMSEs at 120 s against entry 158's; a row with ordinary use per unit."""
    keys = list(KEYS.values())
    mine = {r["unit"]: [r[k] for k in keys] for r in got if r["method"] == ACROSS}
    theirs = {r["unit"]: [r[k] for k in keys] for r in E159["fresh_rows"]()
              if r["method"] == ACROSS and r.get("budget_s") == 120.0}
    use = {r["unit"] for r in got if r["method"] == USE}
    same = "equals" if mine == theirs else "DIFFERS from"
    return f"{len(mine)} units; the plan alone {same} entry 158's; {len(use)} units with ordinary use"


def draw0_rows() -> list[dict]:
    """other16's 16 units in start draw 0 at 120 s (entry 153)."""
    out = []
    for k in E157["FOLDS"]:
        out += [r for r in E157["metrics"](E157["o16"](HERE.parent / "entry153", 0, k))
                if r["method"] == "per_unit" or (r["method"] in (ACROSS, USE) and r.get("budget_s") == 120.0)]
    return out


def main() -> None:
    got = rows()
    print(f"rule 1: {gate(got)}")
    text = "{:.3f}x [{:.2f}, {:.2f}]".format
    print("\nrule 2, 120 s, RMSE over the unit's own reference, mean over units [95% interval], "
          "force / angle")
    print("| plan | 128 fresh units (SIM25-*) | other16's 16 units, start draw 0 |")
    print("|---|---|---|")
    fresh = {n: unit_ratios(got, k) for n, k in KEYS.items()}
    other = {n: unit_ratios(draw0_rows(), k) for n, k in KEYS.items()}
    for method in (USE, ACROSS):
        cells = [" / ".join(text(*mean_interval(list(r[n][method, 120.0].values()))) for n in KEYS)
                 for r in (fresh, other)]
        print(f"| {method} | " + " | ".join(cells) + " |")
    for n in KEYS:
        use, alone = fresh[n][USE, 120.0], fresh[n][ACROSS, 120.0]
        print(f"with ordinary use over the plan alone, per fresh unit, {n}: "
              f"x{paired_text([use[u] / alone[u] for u in sorted(use)])}")
    goal = [mean_interval(list(fresh[n][USE, 120.0].values())) for n in KEYS]
    met = all(m <= 1.10 and hi <= 1.25 for m, _, hi in goal)
    print(f"\nrule 3: the 120 s goal with ordinary use on the fresh units: {'met' if met else 'missed'}")


if __name__ == "__main__":
    main()
