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

from anytip.uncertainty.fleet_margin import IN_BAND_SHARE, MARGIN_GRID, Learner, left_out_widths, margin_over

G = Path("reports/cross_sensor_response_gpu")
E113 = runpy.run_path(str(G / "entry113/analyse.py"))  # SETS, KINDS, learners, held_out, row_array, target
SETS = {**E113["SETS"], "112": [G / f"entry112/fleet88r_apart/fleet88_seed{k}" for k in (0, 1)]}
KINDS = E113["KINDS"]
HELD_OUT = 440  # fleet88's held-out unit-outputs


def left_out(folds: list[list[Learner]]) -> tuple[np.ndarray, ...]:
    """The folds' left-out half-widths (`fleet_margin.left_out_widths`: each learner's own times the
    factor of the others) and those at the floor and the band's edges, each flattened and joined."""
    parts = [left_out_widths(fold) for fold in folds]
    return tuple(np.concatenate([p[i].ravel() for p in parts]) for i in range(4))


def tail_table(kind: str) -> str:
    """Rule 1 for one kind on entry 112's learners (the grid's counts from `fleet_margin.margin_over`)."""
    base, floor, low, high = left_out([E113["learners"](run, k, kind) for k, run in enumerate(SETS["112"])])
    z = np.log(floor / base)
    mu, sd = z.mean(), z.std(ddof=1)
    grid = margin_over(base, floor, low, high)
    lines = [f"  {kind or 'plan '}: log(at_floor / width) mean {mu:.3f}, sd {sd:.3f}, over {len(z)}"]
    for m in MARGIN_GRID:
        expected = HELD_OUT * norm.sf((np.log(m) - mu) / sd)
        lines.append(f"    margin {m:g}: learners below {grid.below[m]}, in band {grid.in_band[m]:.0%}; "
                     f"normal tail, below of {HELD_OUT} {expected:.2f}, none below {np.exp(-expected):.2f}")
    return "\n".join(lines)


def largest_margin(fold: list[Learner]) -> float | None:
    """The largest grid margin whose left-out learners keep `IN_BAND_SHARE` in the band; None if none."""
    band = margin_over(*left_out([fold])).in_band
    ok = [m for m in MARGIN_GRID if band[m] >= IN_BAND_SHARE]
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
