"""Research log entry 107: the fallback margin (F) against the learners' rule on 64 fresh held-out units
(SIM42-*, 32 under each of entry 106's folds). Prints rule 1 (the learners' margin records against entry
106's), rule 2 (the recipe's intervals on the fresh units, `margin_` fields) and rule 3 (F's margin per fold
and row, and the unit-outputs below 0.80 and in the band under the rule and under F). From the repository
root:

    python reports/cross_sensor_response_gpu/entry107/analyse.py
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from anytip.pipelines.cross_sensor_jobs import band_edges, needed_key
from anytip.rundir import read_json
from anytip.uncertainty.fleet_margin import IN_BAND_SHARE, meeting

G = Path("reports/cross_sensor_response_gpu")
RUNS = [G / f"entry107/fleet88w_seed{k}" for k in (0, 1)]
CONTROL = [G / f"entry106/fleet88_cpu_use/fleet88_seed{k}" for k in (0, 1)]
ROWS = {"response@cover_informative": "margin_by_strategy",
        "response+use@cover_informative": "use_margin_by_strategy"}
OUTPUTS = ("fx", "fy", "fz", "theta", "phi")
FLOOR, LOW, HIGH = band_edges(0.9)


def record(run: Path, seed: int, key: str) -> dict[str, Any]:
    """A fold's recorded margin choice, `cover_informative` at 120 s: margin, below_floor, in_band."""
    header = read_json(run / f"models/response_seed{seed}.json")
    return header.get("meta", header)["intervals"][key]["cover_informative"]["120"]


def fallback(rec: dict[str, Any]) -> float:
    """F: the rule's margin where a grid value meets it; else the smallest of those with at least
    `IN_BAND_SHARE` in the band that leave the fewest left-out unit-outputs below the floor; else 1."""
    below = {float(m): int(n) for m, n in rec["below_floor"].items()}
    in_band = {float(m): float(v) for m, v in rec["in_band"].items()}
    ok = meeting(below, in_band, IN_BAND_SHARE)
    if ok:
        return min(ok)
    banded = [m for m in below if in_band[m] >= IN_BAND_SHARE]
    if not banded:
        return 1.0
    fewest = min(below[m] for m in banded)
    return min(m for m in banded if below[m] == fewest)


def scored(rows: list[dict[str, Any]], factor: float | None) -> tuple[list[str], float, int]:
    """The unit-outputs below the floor, the share in the band and their count, with each row's fleet
    half-width times `factor` (None: the row's own `margin_` half-width, the rule's)."""
    low_ones, inside = [], []
    for r in rows:
        for o in OUTPUTS:
            w = r[f"{o}_margin_halfwidth"] if factor is None else r[f"{o}_fleet_halfwidth"] * factor
            inside.append(r[needed_key(o, LOW)] <= w <= r[needed_key(o, HIGH)])
            if w < r[needed_key(o, FLOOR)]:
                low_ones.append(f"{r['unit']} {o} {w / r[needed_key(o, FLOOR)]:.3f}")
    return low_ones, float(np.mean(inside)), len(inside)


def main() -> None:
    print("rule 1 (the learners' margin records against entry 106's):")
    for seed, (run, control) in enumerate(zip(RUNS, CONTROL, strict=True)):
        for method, key in ROWS.items():
            mine, theirs = record(run, seed, key), record(control, seed, key)
            print(f"  fold {seed} {method}: {'equal' if mine == theirs else 'DIFFERENT'}; margin "
                  f"{mine['margin']:g} (entry 106: {theirs['margin']:g})")
    totals = {"rule": 0, "F": 0}
    for method, key in ROWS.items():
        print(f"\n{method}:")
        for name in ("rule", "F"):
            low_ones, share, n = [], [], 0
            for seed, run in enumerate(RUNS):
                rows = [r for r in read_json(run / "rows.json")["rows"] if r["method"] == method]
                rec = record(run, seed, key)
                factor = None if name == "rule" else fallback(rec)
                lo, sh, k = scored(rows, factor)
                low_ones += lo
                share.append(sh * k)
                n += k
                print(f"  {name} fold {seed}: margin {rec['margin'] if factor is None else factor:g}, "
                      f"{len(rows)} units")
            totals[name] += len(low_ones)
            print(f"  {name}: {sum(share) / n:.1%} of {n} in [{LOW:.2f}, {HIGH:.2f}], {len(low_ones)} below "
                  f"{FLOOR:.2f} (width over the floor's: {', '.join(low_ones) or 'none'})")
    print(f"\nbelow {FLOOR:.2f}, both rows: rule {totals['rule']}, F {totals['F']}")


if __name__ == "__main__":
    main()
