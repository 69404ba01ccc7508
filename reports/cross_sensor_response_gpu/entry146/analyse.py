"""Research log entry 146's reading: the designed plan of budget B read from the design of 1.25 B, cut at
B (`options.designed_scale`), against the design of B itself in the runs behind the cells. Rule 1 (gate): each
new run's references and `cover_informative` rows equal its base run's (plans equal, RMSEs within the drift
reported), every designed plan within B seconds. Rule 2: the filled plan's ratios, each unit's draws averaged,
alone and with ordinary use, and filled over in place per unit. Rule 3: without session conditions (other16sg,
draw 0), filled over in place per unit, and the with-session gain's excess over it. Reads what has run.
Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry146/analyse.py
"""

from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
GPU = HERE.parent
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
USES = ("response", "response+use")
SHARED = tuple(f"{u}@cover_informative" for u in USES)
DESIGNED = tuple(f"{u}@designed" for u in USES)


def other16(root: Path, d: int, k: int) -> Path:
    return root / f"other16_severe_d{d}" / f"other16_seed{k}"


def base_other16(budget: int, d: int, k: int) -> Path:
    """The run behind the cell: entry 142 (draw 0) and 144 at 600 s, entry 130 at 120 s."""
    if budget == 120:
        return other16(GPU / "entry130", d, k)
    return other16(GPU / ("entry142" if d == 0 else "entry144"), d, k)


def base_fleet88(budget: int, k: int) -> Path:
    return GPU / ("entry143" if budget == 600 else "entry131") / f"fleet88_seed{k}"


def rows(run: Path) -> list[dict[str, Any]]:
    return read_json(run / "metrics.json")["results"]


def done(run: Path) -> bool:
    return (run / "metrics.json").is_file()


def gate(new: Path, old: Path, budget: int) -> str:
    """Rule 1 for one pair of runs, as a line."""
    a, b = rows(new), rows(old)

    def plans(got: list[dict[str, Any]]) -> list[tuple[Any, ...]]:
        return sorted((r["method"], r["unit"], r["seed"], r["calib_samples"], r["calib_seconds"])
                      for r in got if r["method"] in SHARED and r["budget_s"] == budget)

    def references(got: list[dict[str, Any]]) -> list[tuple[Any, ...]]:
        return sorted(tuple(sorted(r.items())) for r in got if r["method"] == "per_unit")

    def rmses(got: list[dict[str, Any]]) -> np.ndarray:
        return np.array([r[key] for r in sorted(got, key=lambda r: (r["method"], r["unit"]))
                         if r["method"] in SHARED and r["budget_s"] == budget for key in KEYS.values()])

    if not plans(a):  # a run of the designed plans alone (fleet88): its references are the gate
        equal, drift = references(a) == references(b), 0.0
    else:
        equal = plans(a) == plans(b) and references(a) == references(b)
        drift = float(np.max(np.abs(rmses(a) / rmses(b) - 1)))
    most = max(r["calib_seconds"] for r in a if r["method"] in DESIGNED and r["budget_s"] == budget)
    return (f"references and cover_informative plans {'equal' if equal else 'DIFFER'}, RMSEs within "
            f"{drift:.4f} relative; designed plans at most {most:.1f} s")


def per_unit(got: list[dict[str, Any]], method: str, budget: int) -> dict[str, dict[str, float]]:
    """Per output kind, per unit: the method's ratio to the unit's reference at `budget`, seeds and draws
    averaged."""
    return {label: unit_ratios(got, key)[(method, float(budget))] for label, key in KEYS.items()}


def line(per: dict[str, dict[str, float]]) -> str:
    """Each output kind's mean over units with its 95% interval, to three decimals (cells near a goal)."""
    stats = {label: mean_interval(list(per[label].values())) for label in KEYS}
    return (", ".join(f"{label} {m:.3f}x [{lo:.3f}, {hi:.3f}]" for label, (m, lo, hi) in stats.items())
            + f" over {len(per['force'])} units")


def over(a: dict[str, dict[str, float]], b: dict[str, dict[str, float]]) -> str:
    return ", ".join(f"{label} x{paired_text([a[label][u] / b[label][u] for u in b[label]])}"
                     for label in KEYS)


def ratio_of(a: dict[str, dict[str, float]], b: dict[str, dict[str, float]]) -> dict[str, dict[str, float]]:
    return {label: {u: a[label][u] / b[label][u] for u in b[label]} for label in KEYS}


def plan_size(got: list[dict[str, Any]], budget: int) -> str:
    """The designed plans' seconds and presses (mean and range over the rows)."""
    r = [(x["calib_seconds"], x["presses"]) for x in got if x["method"] == "response@designed"
         and x["budget_s"] == budget]
    s, p = np.array(r).T
    return (f"{s.mean():.1f} s [{s.min():.1f}, {s.max():.1f}], "
            f"{p.mean():.1f} presses [{p.min():.0f}, {p.max():.0f}]")


def read_cell(name: str, pairs: list[tuple[str, Path, Path]], budget: int) -> dict[str, Any]:
    """Rules 1 and 2 for one registry and budget; `pairs`: (label, new run, base run) that have run."""
    print(f"== {name}, {budget} s: {len(pairs)} runs")
    for label, new, old in pairs:
        print(f"  rule 1, {label}: {gate(new, old, budget)}")
    new_rows = [r for _, new, _ in pairs for r in rows(new)]
    old_rows = [r for _, _, old in pairs for r in rows(old)]
    print(f"  designed plans, filled: {plan_size(new_rows, budget)}; in place: {plan_size(old_rows, budget)}")
    got = {}
    for m in DESIGNED + SHARED:  # a run of the designed plans alone reads `cover_informative` in its base run
        got[("filled", m)] = per_unit(new_rows if any(r["method"] == m for r in new_rows) else old_rows,
                                      m, budget)
        got[("in place", m)] = per_unit(old_rows, m, budget)
    for m in DESIGNED:
        print(f"  rule 2, {m}: filled {line(got[('filled', m)])}")
        print(f"  {'':>{len('rule 2, ') + len(m)}}  in place {line(got[('in place', m)])}")
        print(f"    filled over in place, per unit: {over(got[('filled', m)], got[('in place', m)])}")
        print(f"    filled over {m.split('@')[0]}@cover_informative: "
              f"{over(got[('filled', m)], got[('filled', m.split('@')[0] + '@cover_informative')])}")
    for m in SHARED:
        print(f"  {m} (the same runs): {line(got[('filled', m)])}")
    return got


def main() -> None:
    cells = {}
    for budget in (600, 120):
        pairs = [(f"draw {d} fold {k}", other16(HERE / f"at{budget}", d, k), base_other16(budget, d, k))
                 for d in (0, 1, 2) for k in range(4)]
        pairs = [p for p in pairs if done(p[1])]
        if pairs:
            cells[("other16", budget)] = read_cell("other16", pairs, budget)
        pairs = [(f"fold {k}", HERE / f"at{budget}" / f"fleet88_seed{k}", base_fleet88(budget, k))
                 for k in (0, 1)]
        pairs = [p for p in pairs if done(p[1])]
        if pairs:
            read_cell("fleet88", pairs, budget)
    runs = [(other16(HERE / "nosessions", 0, k), other16(HERE / "nosessions_in_place", 0, k))
            for k in range(4)]
    runs = [r for r in runs if done(r[0]) and done(r[1])]
    if not runs:
        return
    print(f"== other16 without session conditions (other16sg), draw 0: {len(runs)} folds")
    filled = [r for new, _ in runs for r in rows(new)]
    in_place = [r for _, old, in runs for r in rows(old)]
    for budget in (600, 120):
        print(f"  {budget} s: designed plans, filled: {plan_size(filled, budget)}; "
              f"in place: {plan_size(in_place, budget)}")
        for m in DESIGNED:
            a, b = per_unit(filled, m, budget), per_unit(in_place, m, budget)
            print(f"  rule 3, {m}: filled over in place without sessions {over(a, b)}")
            if ("other16", budget) in cells:
                with_sessions = [r for d, k in ((0, k) for k in range(4))
                                 for r in rows(other16(HERE / f"at{budget}", d, k))]
                before = [r for k in range(4) for r in rows(base_other16(budget, 0, k))]
                now, then = per_unit(with_sessions, m, budget), per_unit(before, m, budget)
                print(f"    with sessions, draw 0: {over(now, then)}")
                gain = ratio_of(now, then)
                print(f"    the with-session gain over it (the longer runs' excess): "
                      f"{over(gain, ratio_of(a, b))}")


if __name__ == "__main__":
    main()
