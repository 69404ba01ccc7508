"""Research log entry 171: `anytip calibrate`'s fit-and-fold seconds against the speed of the core that spent
them.

Reads entry 116's timing run twice in one session: part A (logs/time_A.log; lines 'ARM UNIT round R wall_s S
command_s C core_gflops G') and part B, the calibrations of entry 172's alternated timing that ran entry 171's
code (entry172/logs/time_calibrate.log, lines 'old ARM UNIT ...'); and the probe's own seconds
(logs/probe.log). Prints the readings the entry wrote down before it ran:

    python reports/cross_sensor_response_gpu/entry171/analyse.py > \
        reports/cross_sensor_response_gpu/entry171/logs/analyse.log
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy import stats

LOGS = Path(__file__).parent / "logs"
PART_LOGS = {"A": (LOGS / "time_A.log", None),  # part -> (log, the code its lines name first)
             "B": (LOGS.parent.parent / "entry172" / "logs" / "time_calibrate.log", "old")}
PARTS = tuple(PART_LOGS)
TARGET_S = 10.0
SPREAD_TO_TEST = 1.05  # rule 2: the probe's spread over the session that puts the scaling to the test


def timing_line(line: str) -> dict | None:
    """A line of entry 116's `time_one` ('ARM UNIT round R wall_s S command_s C [core_gflops G]', a wrapper's
    CODE first and more 'KEY VALUE' pairs after it allowed) as {code (None without one), arm, unit, round, and
    each KEY: its VALUE as text}; None for any other line. Entries 171 and 172 read their logs with it."""
    w = line.split()
    code = None
    if len(w) > 3 and w[3] == "round":
        code, w = w[0], w[1:]
    if len(w) < 4 or w[2] != "round" or len(w) % 2:  # the fields after the round come in pairs
        return None
    pairs = dict(zip(w[4::2], w[5::2], strict=True))
    return {"code": code, "arm": w[0], "unit": w[1], "round": int(w[3]), **pairs}


def timings() -> list[dict]:
    """One row per calibration: part, arm, unit, round, wall_s, command_s, core_gflops, work."""
    rows = []
    for part, (path, code) in PART_LOGS.items():
        if not path.exists():
            continue
        for t in map(timing_line, path.read_text().splitlines()):
            if t is None or t["code"] != code or "core_gflops" not in t:
                continue
            wall, gflops = float(t["wall_s"]), float(t["core_gflops"])
            rows.append({"part": part, "arm": t["arm"], "unit": t["unit"], "round": t["round"],
                         "wall_s": wall, "command_s": float(t["command_s"]), "core_gflops": gflops,
                         "work": wall * gflops})
    return rows


def scaling_slope(rows: list[dict]) -> tuple[float, float, float]:
    """Rule 2: the slope of log wall_s on log core_gflops, a mean per (arm, unit), with its 95% interval."""
    groups = sorted({(r["arm"], r["unit"]) for r in rows})
    x, y = [], []
    for g in groups:
        mine = [r for r in rows if (r["arm"], r["unit"]) == g]
        lx = np.log([r["core_gflops"] for r in mine])
        ly = np.log([r["wall_s"] for r in mine])
        x += list(lx - lx.mean())
        y += list(ly - ly.mean())
    x, y = np.array(x), np.array(y)
    slope = float(x @ y / (x @ x))
    dof = len(x) - len(groups) - 1
    resid = y - slope * x
    se = np.sqrt(resid @ resid / dof / (x @ x))
    half = stats.t.ppf(0.975, dof) * se
    return slope, slope - half, slope + half


def main() -> None:
    rows = timings()
    if not rows:
        print("no timing logs yet")
        return
    print("rule 1, per calibration (one core, the other idle)")
    print("| part | arm | unit | round | wall_s | core_gflops | work (GFLOP) |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['part']} | {r['arm']} | {r['unit']} | {r['round']} | {r['wall_s']:.2f} | "
              f"{r['core_gflops']:.1f} | {r['work']:.0f} |")
    print("\n| part | arm | calibrations | wall_s | core_gflops | work (GFLOP) |")
    print("|---|---|---|---|---|---|")
    for part in [p for p in PARTS if any(r["part"] == p for r in rows)] + ["both"]:
        for arm in ("alone", "use"):
            mine = [r for r in rows if r["arm"] == arm and part in ("both", r["part"])]
            span = {k: (min(r[k] for r in mine), max(r[k] for r in mine))
                    for k in ("wall_s", "core_gflops", "work")}
            print(f"| {part} | {arm} | {len(mine)} | {span['wall_s'][0]:.2f}-{span['wall_s'][1]:.2f} | "
                  f"{span['core_gflops'][0]:.1f}-{span['core_gflops'][1]:.1f} | "
                  f"{span['work'][0]:.0f}-{span['work'][1]:.0f} |")
    g = [r["core_gflops"] for r in rows]
    spread = max(g) / min(g)
    print(f"\nthe probe over the session: {min(g):.1f}-{max(g):.1f} GFLOP/s, spread x{spread:.3f}")
    if spread >= SPREAD_TO_TEST:
        slope, lo, hi = scaling_slope(rows)
        verdict = "proportional" if lo <= -1 <= hi else "NOT proportional"
        print(f"rule 2: slope of log wall_s on log core_gflops {slope:.2f} [{lo:.2f}, {hi:.2f}]: {verdict}")
    else:
        print(f"rule 2: under x{SPREAD_TO_TEST:.2f} of spread: the scaling is untested here, an assumption")
    print("\nrule 3, the threshold: the largest work over units and rounds / 10 s")
    for arm in ("alone", "use"):
        mine = [r for r in rows if r["arm"] == arm]
        need = max(r["work"] for r in mine) / TARGET_S
        today = float(np.median([r["core_gflops"] for r in mine]))
        under = sum(r["wall_s"] < TARGET_S for r in mine)
        where = f"x{need / today:.2f} short of it" if need > today else "at or above it"
        print(f"{arm}: met on cores of >= {need:.0f} GFLOP/s; today's core {today:.1f} GFLOP/s (median), "
              f"{where}; {under} of {len(mine)} calibrations under {TARGET_S:g} s today")
    probe = LOGS / "probe.log"
    if probe.exists():
        print(f"\nrule 4, the probe's own seconds: {probe.read_text().strip()}")


if __name__ == "__main__":
    main()
