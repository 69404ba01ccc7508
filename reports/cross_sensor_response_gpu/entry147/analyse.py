"""Research log entry 147: the designed plan's intervals at 120 s on fleet88's 88 held-out units, tested on
both their sessions (entry 146's rescoring with entry 110's intervals and `splits.test_rows: all_sessions`).
Prints rule 1 (each held-out unit's plan against entry 146's; its test rows against entry 110's count; the
registry's test sessions against data/fleet88r's), rule 2 (the target per method, with its verdict) and,
deciding nothing, each fold's factor and margin, the unit-outputs below 0.80, an exact method's share and
entry 110's `cover_informative` figures beside them. The rescoring keeps the run's per-unit references
(`--paired-only`), so no ratio to them is printed. From the repository root:

    python reports/cross_sensor_response_gpu/entry147/analyse.py
"""

from __future__ import annotations

import runpy
import sqlite3
from pathlib import Path

import h5py
import numpy as np

from anytip.rundir import read_json
from anytip.uncertainty.fleet_margin import factor_ceiling

G = Path("reports/cross_sensor_response_gpu")
RUNS = [G / f"entry147/at120/fleet88_seed{k}" for k in (0, 1)]
RUNS_COVER = [G / f"entry147/cover120/fleet88_seed{k}" for k in (0, 1)]  # the second arm, same test rows
PLANS_146 = [G / f"entry146/at120/fleet88_seed{k}" for k in (0, 1)]
COVER_110 = [G / f"entry110/fleet88r_both/fleet88_seed{k}" for k in (0, 1)]
METHODS = ("response@designed", "response+use@designed")
COVER = ("response@cover_informative", "response+use@cover_informative")
ANALYSE_106 = runpy.run_path(str(G / "entry106/analyse.py"))  # rows_by_unit, same, below
ANALYSE_108 = runpy.run_path(str(G / "entry108/analyse.py"))  # intervals, OUTPUTS
ANALYSE_110 = runpy.run_path(str(G / "entry110/analyse.py"))  # met
rows_by_unit, same, OUTPUTS = ANALYSE_106["rows_by_unit"], ANALYSE_106["same"], ANALYSE_108["OUTPUTS"]


def test_sessions_equal(a: Path = Path("data/fleet88h"), b: Path = Path("data/fleet88r")) -> str:
    """How many of registry `a`'s test-session runs equal `b`'s, by unit and orientation: the same content
    hash in both catalogs, or else the same pressures, forces and angles in both files."""
    def runs(reg: Path) -> dict[tuple[str, float], tuple[str, Path]]:
        with sqlite3.connect(reg / "catalog.sqlite") as db:
            got = db.execute("select unit, orientation_deg, sha256, path from runs where protocol = 'retest'")
            return {(u, o): (h, reg / path) for u, o, h, path in got}

    mine, theirs = runs(a), runs(b)
    if set(mine) != set(theirs):
        return f"the test sessions differ in which runs they hold ({len(mine)} against {len(theirs)})"
    equal = 0
    for key, (digest, path) in mine.items():
        if digest == theirs[key][0]:
            equal += 1
            continue
        with h5py.File(path) as f, h5py.File(theirs[key][1]) as g:
            equal += all(np.array_equal(f[k][()], g[k][()]) for k in ("pressure", "force", "angles"))
    return f"{equal} of {len(mine)} test-session runs equal {b}'s"


def rule_1() -> str:
    """Plans against entry 146's, test rows against entry 110's, test sessions against data/fleet88r's; the
    second arm's plans and plan-alone own half-widths against entry 110's."""
    plan = ["calib_seconds", "presses"]
    lines = [f"  {m} plans (seconds, presses) against entry 146: "
             f"{same(rows_by_unit(RUNS, m), rows_by_unit(PLANS_146, m), plan)}"
             for m in METHODS]
    now, then = rows_by_unit(RUNS, METHODS[0]), rows_by_unit(COVER_110, COVER[0])
    rows = sum(now[u]["interval_test_rows"] == then[u]["interval_test_rows"] for u in now)
    lines.append(f"  test rows equal entry 110's in {rows} of {len(now)} units")
    lines.append(f"  {test_sessions_equal()}")
    if all((r / "metrics.json").exists() for r in RUNS_COVER):
        halves = [f"{o}_halfwidth" for o in OUTPUTS]
        for m in COVER:
            lines.append(f"  second arm, {m} plans against entry 110: "
                         f"{same(rows_by_unit(RUNS_COVER, m), rows_by_unit(COVER_110, m), plan)}")
        lines.append(f"  second arm, {COVER[0]} own half-widths against entry 110: "
                     f"{same(rows_by_unit(RUNS_COVER, COVER[0]), rows_by_unit(COVER_110, COVER[0]), halves)}")
    return "rule 1:\n" + "\n".join(lines)


def below_both(method: str, cover: str) -> str:
    """The unit-outputs below the floor for the designed plan and for `cover_informative` on the same rows."""
    a = {" ".join(c.split()[:2]) for c in ANALYSE_106["below"](rows_by_unit(RUNS, method), "margin")}
    b = {" ".join(c.split()[:2]) for c in ANALYSE_106["below"](rows_by_unit(RUNS_COVER, cover), "margin")}
    return (f"  {method} below 0.80: {len(a)}; {cover}: {len(b)}; both: {', '.join(sorted(a & b)) or 'none'}")


def factors(run: Path, seed: int, strategy: str = "designed", budget: str = "120") -> str:
    """A fold's fleet factors and margins for `strategy`'s plan at `budget` robot seconds, alone and with
    ordinary use, as recorded."""
    header = read_json(run / f"models/response_seed{seed}.json")
    iv = header.get("meta", header)["intervals"]
    lines = []
    for prefix, label in (("", "plan alone"), ("use_", "with use")):
        factor, margin = (iv[f"{prefix}{k}_by_strategy"][strategy][budget]
                          for k in ("fleet_factor", "margin"))
        cells = ", ".join(f"{o} {factor[o]:.2f}" for o in OUTPUTS)
        lines.append(f"  fold {seed} {label}: factor {cells}; margin {margin['margin']:g} "
                     f"(learners below 0.80 by margin: {margin['below_floor']})")
    return "\n".join(lines)


def ceiling(runs: list[Path], method: str, width: str = "fleet_halfwidth") -> str:
    """The best single factor per output on the held-out units' `width` (own x their fold's factor unless
    named otherwise; `uncertainty.fleet_margin.factor_ceiling`), in words."""
    rows = rows_by_unit(runs, method)

    def field(key: str) -> np.ndarray:
        return np.array([[r[f"{o}_{key}"] for o in OUTPUTS] for r in rows.values()])

    c = factor_ceiling(field(width), *(field(f"needed{q}_halfwidth") for q in (80, 85, 95)))
    return f"at most {c.free_in_band:.0%} in the band, {c.safe_in_band:.0%} with none below 0.80"


def main() -> None:
    print(rule_1())
    arms = [(RUNS, METHODS, "designed")]
    if all((r / "metrics.json").exists() for r in RUNS_COVER):
        arms.append((RUNS_COVER, COVER, "cover_informative"))
    print("\nrule 2, the target on both sessions' rows (440 unit-outputs a method):")
    for runs, methods, _ in arms:
        for m in methods:
            print(f"{ANALYSE_108['intervals'](runs, m)}\n    verdict: "
                  f"{'met' if ANALYSE_110['met'](rows_by_unit(runs, m)) else 'missed'}")
    print("\nalso read (decides nothing): each fold's factor and margin")
    for runs, _, strategy in arms:
        for seed, run in enumerate(runs):
            print(factors(run, seed, strategy))
    if len(arms) > 1:
        print("the unit-outputs below 0.80, by plan, on the same test rows:")
        for m, c in zip(METHODS, COVER, strict=True):
            print(below_both(m, c))
    print("entry 110's cover_informative, on fleet88r's test sessions (the recipe before entry 131):")
    for m in COVER:
        print(ANALYSE_108["intervals"](COVER_110, m))


if __name__ == "__main__":
    main()
