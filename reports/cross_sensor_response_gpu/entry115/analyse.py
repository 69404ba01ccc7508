"""Research log entry 115, exploratory: what "none below 0.80" asks of a margin, given the learners' spread.

1. On entry 112's learners (28 per fold, both folds: 280 left-out unit-outputs per kind), per margin on the
   grid: the left-out unit-outputs below 0.80 and the share in [0.85, 0.95]; and, from a normal fitted to
   log(at_floor / width), the expected number below 0.80 among 440 unit-outputs and the chance that none is.
2. Today's margin (the smallest that meets the learners' rule, else 1) against the largest whose left-out
   learners keep the band's share (`IN_BAND_SHARE`), applied to the held-out units of entries 106-112's
   records (seen before: a read, not a test).
From the repository root:

    python reports/cross_sensor_response_gpu/entry115/analyse.py
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np
from scipy.stats import norm

from anytip.uncertainty.fleet_margin import IN_BAND_SHARE, MARGIN_GRID, Learner, left_out_widths

G = Path("reports/cross_sensor_response_gpu")
E113 = runpy.run_path(str(G / "entry113/analyse.py"))  # SETS, KINDS, learners, held_out, row_array, target
SETS = {**E113["SETS"], "112": [G / f"entry112/fleet88r_apart/fleet88_seed{k}" for k in (0, 1)]}
KINDS = E113["KINDS"]
HELD_OUT = 440  # fleet88's held-out unit-outputs


def left_out_logs(fold: list[Learner]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """log(at_floor, at_low, at_high / width) of each left-out learner-output, width its own times the
    factor of the others, flattened."""
    base, floor, low, high = left_out_widths(fold)
    return tuple(np.log(x / base).ravel() for x in (floor, low, high))


def tail_table(kind: str) -> str:
    """Rule 1 for one kind on entry 112's learners."""
    parts = [left_out_logs(E113["learners"](run, k, kind)) for k, run in enumerate(SETS["112"])]
    floor, low, high = (np.concatenate([p[i] for p in parts]) for i in range(3))
    mu, sd = floor.mean(), floor.std(ddof=1)
    lines = [f"  {kind or 'plan '}: log(at_floor / width) mean {mu:.3f}, sd {sd:.3f}, over {len(floor)}"]
    for m in MARGIN_GRID:
        lm = np.log(m)
        expected = HELD_OUT * norm.sf((lm - mu) / sd)
        lines.append(f"    margin {m:g}: learners below {int((floor > lm).sum())}, in band "
                     f"{((low <= lm) & (lm <= high)).mean():.0%}; normal tail, below of {HELD_OUT} "
                     f"{expected:.2f}, none below {np.exp(-expected):.2f}")
    return "\n".join(lines)


def largest_margin(fold: list[Learner]) -> float | None:
    """The largest grid margin whose left-out learners keep `IN_BAND_SHARE` in the band; None if none."""
    floor, low, high = left_out_logs(fold)
    ok = [m for m in MARGIN_GRID if ((low <= np.log(m)) & (np.log(m) <= high)).mean() >= IN_BAND_SHARE]
    return max(ok) if ok else None


def rules(name: str, kind: str) -> str:
    """Rule 2 for one record set and kind."""
    tally: dict[str, list] = {"today": [], "largest": []}
    margins = []
    for k, run in enumerate(SETS[name]):
        rows = E113["held_out"](run, KINDS[kind])
        fleet = E113["row_array"](rows, "fleet_halfwidth")
        today = E113["row_array"](rows, "margin_halfwidth")
        was = float(np.median(today / fleet))
        now = largest_margin(E113["learners"](run, k, kind)) or was
        margins.append(f"{was:.2f}->{now:g}")
        tally["today"].append((today, rows))
        tally["largest"].append((fleet * now, rows))
    cells = []
    for rule, parts in tally.items():
        below, band = E113["target"](np.concatenate([p[0] for p in parts]), [r for p in parts for r in p[1]])
        cells.append(f"{rule}: below {below}, in band {band:.1%}")
    return f"  {name} {kind or 'plan'} (margins {', '.join(margins)}): {'; '.join(cells)}"


def main() -> None:
    print("1. entry 112's learners, left out in turn:")
    for kind in KINDS:
        print(tail_table(kind))
    print("\n2. held-out units, today's margin against the largest that keeps the learners' band share:")
    for name in SETS:
        for kind in KINDS:
            print(rules(name, kind))


if __name__ == "__main__":
    main()
