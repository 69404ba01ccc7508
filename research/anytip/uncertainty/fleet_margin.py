"""A margin on the fleet factor, chosen by leaving one learning unit out at a time.

A new unit's half-width is its plan's own times the fleet factor (`conformal.fleet_factor`). The
units that learn the factor (validation and factor units) can also say how often that rule lets a
unit's coverage fall outside a band: each in turn gets the factor of the others, and its test rows
say where its coverage lands (`Learner.needed_*`, the half-widths at which it is at the band's
edges and at its floor). The margin is the smallest factor multiplier on a grid under which no
left-out unit-output falls below the floor and at least `in_band_share` of them lie in the band;
1 where none is.

`factor_ceiling` asks the converse question of units whose test rows are already scored: the most
unit-outputs any one factor per output could put in the band, with and without the condition that
none fall below the floor. It chooses nothing: it says whether a fleet factor, however learnt, can
meet a coverage target on those units, or whether the units' own widths must carry more.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from anytip.uncertainty.conformal import fleet_factor

MARGIN_GRID = tuple(round(1 + 0.02 * k, 2) for k in range(11))  # 1.00, 1.02, ..., 1.20
IN_BAND_SHARE = 0.9  # of left-out unit-outputs within the band, besides none below the floor


class Learner(NamedTuple):
    """One learning unit's half-widths per output (D,), in the output's unit: its plan's own, the
    one its test rows needed at the nominal level, and those at which their coverage is the floor,
    the band's lower and its upper edge."""

    own: np.ndarray
    needed: np.ndarray
    at_floor: np.ndarray
    at_low: np.ndarray
    at_high: np.ndarray

    @classmethod
    def from_record(cls, record: object, names: Sequence[str]) -> Learner:
        """A learner as a response model's benchmark records it: {field: {output: half-width}} for
        every field and output name; ValueError naming the first that is missing or not a finite
        positive number."""
        fields = []
        for f in cls._fields:
            got = record.get(f) if isinstance(record, dict) else None
            values = [got.get(n) if isinstance(got, dict) else None for n in names]
            for n, v in zip(names, values, strict=True):
                if not isinstance(v, int | float) or isinstance(v, bool) or not 0 < v < np.inf:
                    raise ValueError(f"{f}.{n}: {v!r} is not a finite positive half-width")
            fields.append(np.array(values, dtype=float))
        return cls(*fields)


class MarginChoice(NamedTuple):
    """The chosen margin, and per grid value the left-out unit-outputs below the floor and the share
    of them in the band."""

    margin: float
    below: dict[float, int]
    in_band: dict[float, float]

    def shortfall(self, in_band_share: float = IN_BAND_SHARE) -> str | None:
        """Why no margin on the grid met the rule, in words; None where one did (1 included) or
        none was tried (too few learners)."""
        if meeting(self.below, self.in_band, in_band_share) or not self.below:
            return None
        fewest = min(self.below.values())
        if fewest > 0:
            return (f"{fewest} left-out unit-output(s) stayed below the floor at every margin up to "
                    f"{max(self.below):g}")
        first = min(m for m, n in self.below.items() if n == 0)
        return (f"none falls below the floor only from a margin of {first:g}, where "
                f"{self.in_band.get(first, 0.0):.0%} lie in the band (the rule asks {in_band_share:.0%})")


def leave_one_out_margin(learners: Sequence[Learner], in_band_share: float = IN_BAND_SHARE,
                         grid: Sequence[float] = MARGIN_GRID) -> MarginChoice:
    """The margin on the fleet factor by leaving each learner out (see the module); needs >= 3
    learners (a factor of at least two others), else the margin is 1 and the tables are empty."""
    if len(learners) < 3:
        return MarginChoice(1.0, {}, {})
    return margin_over(*left_out_widths(learners), in_band_share, grid)


def margin_over(base: np.ndarray, floor: np.ndarray, low: np.ndarray, high: np.ndarray,
                in_band_share: float = IN_BAND_SHARE, grid: Sequence[float] = MARGIN_GRID) -> MarginChoice:
    """The margin rule on given half-widths (any shape, all alike): `base`, each unit-output's half-width
    before the margin, and those at which its coverage is the floor, the band's lower and upper edge;
    per grid value the unit-outputs below the floor and the share in the band, and the smallest value
    that meets the rule (1 where none does)."""
    below, in_band = {}, {}
    for m in grid:
        width = base * m
        below[m] = int((width < floor).sum())
        in_band[m] = float(((width >= low) & (width <= high)).mean())
    ok = meeting(below, in_band, in_band_share)
    return MarginChoice(min(ok) if ok else 1.0, below, in_band)


def left_out_widths(learners: Sequence[Learner]) -> tuple[np.ndarray, ...]:
    """Per learner and output (U, D): its half-width from the factor of the others (its own times
    `conformal.fleet_factor` of the rest), and the half-widths at which its coverage is the floor, the
    band's lower and its upper edge; needs >= 2 learners (each left out needs another's factor)."""
    own = np.stack([u.own for u in learners])
    needed = np.stack([u.needed for u in learners])
    base = np.stack([u.own * fleet_factor(np.delete(own, k, 0), np.delete(needed, k, 0))
                     for k, u in enumerate(learners)])
    return (base, *(np.stack([getattr(u, f) for u in learners]) for f in ("at_floor", "at_low", "at_high")))


def meeting(below: dict[float, int], in_band: dict[float, float], in_band_share: float) -> list[float]:
    """The margins of a grid that meet the rule: no left-out unit-output below the floor and at
    least `in_band_share` of them in the band."""
    return [m for m, n in below.items() if n == 0 and in_band.get(m, 0.0) >= in_band_share]


def pooled_factor(learners: Sequence[Learner]) -> tuple[np.ndarray, MarginChoice]:
    """The fleet factor (D,) of `learners` (`conformal.fleet_factor` of their own and needed
    half-widths) and the margin on it they choose by leaving each out (`leave_one_out_margin`)."""
    own, needed = np.stack([u.own for u in learners]), np.stack([u.needed for u in learners])
    return fleet_factor(own, needed), leave_one_out_margin(learners)


class FactorCeiling(NamedTuple):
    """Per output (D,): the factor that puts most units in the band (`free`) and the one that does so
    among factors that leave no unit below the floor (`safe`); each one's share of all unit-outputs
    in the band."""

    free: np.ndarray
    free_in_band: float
    safe: np.ndarray
    safe_in_band: float


def factor_ceiling(own: np.ndarray, at_floor: np.ndarray, at_low: np.ndarray,
                   at_high: np.ndarray) -> FactorCeiling:
    """The best one factor per output over units (U, D) of half-widths: their plans' own and those at
    which their test rows' coverage is the floor and the band's edges (see `Learner`). A factor f
    puts unit-output (u, d) in the band where at_low <= f * own <= at_high and below the floor where
    f * own < at_floor; the best f is at some unit's lower edge, so those are the candidates. The
    outputs are chosen independently, so the shares are the means of each output's."""
    own, floor, low, high = (np.asarray(a, dtype=float) for a in (own, at_floor, at_low, at_high))
    lo, hi, need = low / own, high / own, floor / own  # (U, D) band and floor, as factors

    def best(d: int, cands: np.ndarray) -> tuple[float, int]:
        """The candidate factor for output d that puts most units in its band, and how many."""
        inside = ((lo[:, d, None] <= cands) & (cands <= hi[:, d, None])).sum(0)
        k = int(np.argmax(inside))
        return float(cands[k]), int(inside[k])

    free = [best(d, lo[:, d]) for d in range(own.shape[1])]
    least = need.max(0)  # per output, the smallest factor that leaves no unit below the floor
    safe = [best(d, np.append(lo[lo[:, d] >= least[d], d], least[d])) for d in range(own.shape[1])]
    return FactorCeiling(np.array([f for f, _ in free]), sum(n for _, n in free) / own.size,
                         np.array([f for f, _ in safe]), sum(n for _, n in safe) / own.size)
