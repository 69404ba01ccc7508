"""Calibration plans priced in robot time: which whole presses a new unit's calibration holds.

A press is a contiguous segment of contact rows of one run: the rows between the rig
touching the unit and letting go. A plan is a set of whole presses, never isolated rows,
chosen from a unit's recorded runs (any registry: simulated, imported rig logs, full
protocols only) up to a budget of robot seconds. It spreads the presses over the target
space (farthest-point order on each press's mean targets, every target scaled by its own
spread so force and location weigh equally) and so over the rig orientations, which is
where a location lies on the dome; nothing here knows the fingertip's patch grid.

Robot time (`calib_seconds`) counts all rig time the calibration uses:
- each press's own duration (first to last contact row, plus one sample period);
- one move before each press (`RigTiming.move_s`, 2 s where the plan does not know better:
  the selected presses are not the neighbours the recorded protocol visited in turn). A designed
  calibration's presses are taken in recorded order, so each pays its recorded lead instead: the
  time since its run's previous press ended (`move_s` for a run's first press);
- a re-mount for each change of orientation (`RigTiming.remount_s`, 30 s by default).
Presses run grouped by orientation, so a plan with k orientations pays k - 1 re-mounts.

`informative` and `cover_informative` plans choose presses for what they tell a new unit's codes
under a fleet's response model (`CodeInformation`, computed by train/response.py
`press_information`; research log entries 90-91).

Labels of a press are autocorrelated at the rig's sample rate: 1000 rows of one press say
far less than 1000 rows of 100 presses. A plan's effective sample count is its contact
time times `RigTiming.effective_hz` (one independent label per 0.1 s by default, the
shortest shear segment of the built-in protocols), capped at its row count; the adapter
prior is scaled by that count, not by rows.
"""

from __future__ import annotations

import dataclasses
import itertools
import zlib
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy.spatial import cKDTree

from anytip.data.arrays import FleetArrays
from anytip.data.calibration import CalibrationStream
from anytip.data.seeds import unit_seed
from anytip.errors import AnytipError
from anytip.sensor import flat
from anytip.sensor.protocols import (
    PLAN_POINTS,
    design_protocol,
    is_designed,
    is_test_session,
    press_summary,
    waypoints,
)

WAYPOINT_COLUMNS = ("time_s", "orientation_deg", "theta_deg", "phi_deg", "fx_n", "fy_n", "fz_n")

Strategy = Literal["spread", "cover", "random", "first", "designed", "informative", "cover_informative"]
INFORMED: tuple[Strategy, ...] = ("informative", "cover_informative")  # strategies that need CodeInformation
Criterion = Literal["d", "v"]  # what an `informative` plan maximises (CodeInformation)
CRITERIA: tuple[Criterion, ...] = ("d", "v")
MAX_COVER_ORIENTATIONS = 8  # `cover` tries every subset of up to this many orientations (255 plans)
BudgetUnit = Literal["samples", "seconds"]


@dataclass(frozen=True)
class RigTiming:
    """What the rig costs besides contact, in seconds, and how fast labels decorrelate (Hz)."""

    move_s: float = 2.0
    remount_s: float = 30.0
    effective_hz: float = 10.0

    def __post_init__(self) -> None:
        for name in ("move_s", "remount_s"):
            if not np.isfinite(getattr(self, name)) or getattr(self, name) < 0:
                raise AnytipError(f"rig timing {name} must be a finite number >= 0, "
                                  f"got {getattr(self, name)}")
        if not np.isfinite(self.effective_hz) or self.effective_hz <= 0:
            raise AnytipError(f"rig timing effective_hz must be a finite number > 0, got {self.effective_hz}")


@dataclass(frozen=True)
class Presses:
    """A unit's candidate presses, P of them, in recorded order (runs by creation time, then time).

    rows (R,) int64 indices into the FleetArrays, press by press; start (P + 1,) offsets of
    each press in `rows`; run (P,) run index; orientation_deg (P,); duration_s (P,) contact
    seconds; summary (P, d) the press's mean targets, each target scaled by its spread over
    all candidate rows (dimensionless); protocol (P,) object, its run's protocol name or None;
    lead_s (P,) seconds from the end of its run's previous recorded press to its first row (a dropped
    press counts as recorded, so its own time is not paid by the next), NaN for a run's first press.
    """

    rows: np.ndarray
    start: np.ndarray
    run: np.ndarray
    orientation_deg: np.ndarray
    duration_s: np.ndarray
    summary: np.ndarray
    protocol: np.ndarray
    lead_s: np.ndarray

    def __len__(self) -> int:
        return len(self.run)

    def rows_of(self, k: int) -> np.ndarray:
        return self.rows[self.start[k]:self.start[k + 1]]

    def subset(self, keep: np.ndarray) -> Presses:
        """The presses where `keep` (P,) bool holds, in the same order."""
        idx = np.flatnonzero(keep)
        rows, start = _stack([self.rows_of(k) for k in idx])
        return Presses(rows, start, self.run[idx], self.orientation_deg[idx], self.duration_s[idx],
                       self.summary[idx], self.protocol[idx], self.lead_s[idx])

    def moves(self, rig: RigTiming, recorded: bool = False) -> np.ndarray:
        """(P,) seconds of the rig's move before each press: `rig.move_s`, or with `recorded` (presses
        run in recorded order) each press's recorded lead, `move_s` where it has none."""
        if not recorded:
            return np.full(len(self), rig.move_s)
        return np.where(np.isnan(self.lead_s), rig.move_s, self.lead_s)


@dataclass(frozen=True)
class CodeInformation:
    """What each candidate press tells a new unit's codes, linearised at the code prior's mean.

    per_press (P, C, k, k): press p's information about barometer c's code (its effective row
    count over the noise variance times the mean of J J^T over its rows, J the derivative of the
    pressure in the code); prior (C, k, k): the code prior's precision; region (C, k, k): the mean
    of J J^T / noise variance over every candidate row (what the criterion `v` weighs the codes'
    uncertainty by). `criterion`: `d` maximises sum_c log det(posterior precision_c); `v` minimises
    sum_c tr(region_c posterior covariance_c), the linearised pressure variance (in noise
    variances) the codes leave over the region the presses reach.
    """

    per_press: np.ndarray
    prior: np.ndarray
    region: np.ndarray
    criterion: str = "v"

    def value(self, precision: np.ndarray) -> float:
        """The criterion at posterior precision (C, k, k), higher is better."""
        return float(self.values(precision[None])[0])

    def values(self, precision: np.ndarray) -> np.ndarray:
        """(n,) the criterion at n posterior precisions (n, C, k, k), higher is better."""
        if self.criterion == "d":
            return np.linalg.slogdet(precision)[1].sum(-1)
        covariance = np.linalg.inv(precision)
        return -np.einsum("ckj,ncjk->n", self.region, covariance)


@dataclass(frozen=True)
class Plan:
    """A calibration: labeled rows (indices into the FleetArrays, press by press, in the order
    the plan runs them) and what it costs. calib_seconds: robot time, all of it;
    contact_seconds: time in contact; n_effective: the effective labeled sample count;
    bounds (presses + 1,) offsets of each press in `rows` (one block for a stream prefix)."""

    rows: np.ndarray
    presses: int
    calib_seconds: float
    contact_seconds: float
    orientations: tuple[float, ...]
    n_effective: float
    bounds: np.ndarray

    @classmethod
    def empty(cls) -> Plan:
        return cls(np.zeros(0, np.int64), 0, 0.0, 0.0, (), 0.0, np.zeros(1, np.int64))

    def split_presses(self, every: int, fold: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """(fitting rows, check rows): every `every`-th press from press `fold` on (0-based: the
        (fold+1)-th, (fold+every+1)-th, ...) held out whole, for a calibration's own validation;
        folds 0..every-1 hold out each press once. No check rows for fewer than 2 presses, or
        where the fold starts past the last press."""
        fit, check = self.without_presses(every, fold)
        return fit.rows, check

    def without_presses(self, every: int, fold: int = 0) -> tuple[Plan, np.ndarray]:
        """(the plan without its check presses, their rows): `split_presses`' rule, the smaller plan
        with its presses and bounds, and its effective sample count scaled by the rows it keeps (its
        robot and contact seconds are the whole plan's: what the rig spent)."""
        pieces = [self.rows[a:b] for a, b in zip(self.bounds[:-1], self.bounds[1:], strict=True)]
        check = [k for k in range(len(pieces)) if k % every == fold]
        if len(pieces) < 2 or not check:
            return self, self.rows[:0]
        fit = [p for k, p in enumerate(pieces) if k not in check]
        rows = np.concatenate(fit)
        bounds = np.concatenate([[0], np.cumsum([len(p) for p in fit])]).astype(np.int64)
        smaller = dataclasses.replace(self, rows=rows, presses=len(fit), bounds=bounds,
                                      n_effective=self.n_effective * len(rows) / len(self.rows))
        return smaller, np.concatenate([pieces[k] for k in check])


def find_presses(arrays: FleetArrays, unit: str, exclude: np.ndarray | None = None) -> Presses:
    """The unit's presses: rows of one run whose times follow each other within 1.5 sample
    periods. A press with any row where `exclude` (N,) bool holds (a held-out unit's test
    rows) is dropped whole, so a plan never touches test data."""
    if arrays.time is None:
        raise AnytipError("calibration plans need row times; load the runs with load_arrays")
    if unit not in arrays.units:
        raise AnytipError(f"unit {unit!r} is not among the loaded units {arrays.units}")
    mine = np.flatnonzero(arrays.unit == arrays.units.index(unit))
    rank = _recorded_rank(arrays)
    mine = mine[np.lexsort((arrays.time[mine], rank[arrays.run[mine]]))]
    run, t = arrays.run[mine], arrays.time[mine]
    period_of = np.array([r.duration_s / max(r.rows, 1) for r in arrays.runs])  # one sample, s
    period = period_of[run]
    cut = np.flatnonzero((np.diff(run) != 0) | (np.diff(t) > 1.5 * period[1:])) + 1
    bounds = np.concatenate([[0], cut, [len(mine)]]).astype(np.int64)
    lead = _leads(run, t, period, bounds)
    keep = [k for k in range(len(bounds) - 1)
            if exclude is None or not exclude[mine[bounds[k]:bounds[k + 1]]].any()]
    pieces = [mine[bounds[k]:bounds[k + 1]] for k in keep]
    rows, start = _stack(pieces)
    first = np.array([p[0] for p in pieces], np.int64)
    last = np.array([p[-1] for p in pieces], np.int64)
    runs = arrays.run[first].astype(np.int64)
    duration = arrays.time[last] - arrays.time[first] + period_of[runs]
    orientation = np.array([arrays.runs[r].orientation_deg for r in runs], float)
    protocol = np.array([arrays.runs[r].protocol for r in runs], object)
    summary = _summaries(arrays, rows, start)
    return Presses(rows, start, runs, orientation, duration, summary, protocol, lead[keep])


def _leads(run: np.ndarray, t: np.ndarray, period: np.ndarray, bounds: np.ndarray) -> np.ndarray:
    """(K,) seconds from the end of each piece's previous piece of the same run (its last row plus one
    sample period) to its first row; NaN where the piece is its run's first. run, t, period (N,) per
    row in recorded order; bounds (K + 1,) the pieces' offsets."""
    first, last = bounds[:-1], bounds[1:] - 1
    lead = np.full(len(first), np.nan)
    same = run[first[1:]] == run[last[:-1]]
    lead[1:][same] = (t[first[1:]] - t[last[:-1]] - period[last[:-1]])[same]
    return lead


def _stack(pieces: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Row pieces laid end to end: (rows (R,), offsets of each piece (len(pieces) + 1,))."""
    rows = np.concatenate(pieces) if pieces else np.zeros(0, np.int64)
    return rows, np.concatenate([[0], np.cumsum([len(q) for q in pieces], dtype=np.int64)]).astype(np.int64)


def _recorded_rank(arrays: FleetArrays) -> np.ndarray:
    """(R,) each run's place when runs are sorted by creation time, then id (recorded order)."""
    order = sorted(range(len(arrays.runs)), key=lambda k: (arrays.runs[k].created, arrays.runs[k].run_id))
    rank = np.empty(len(order), np.int64)
    rank[order] = np.arange(len(order))
    return rank


def _summaries(arrays: FleetArrays, rows: np.ndarray, start: np.ndarray) -> np.ndarray:
    """(P, d) each press's mean targets, each target divided by its RMS spread over `rows`."""
    y = arrays.targets[rows].astype(np.float64)
    if len(y) == 0:
        return np.zeros((0, y.shape[1]))
    for cols in arrays.slices.values():
        spread = np.sqrt(((y[:, cols] - y[:, cols].mean(0)) ** 2).sum(1).mean())
        y[:, cols] /= max(spread, 1e-12)
    return np.add.reduceat(y, start[:-1], axis=0) / np.diff(start)[:, None]


def select_presses(presses: Presses, budget_s: float, rig: RigTiming = RigTiming(),
                   strategy: Strategy = "spread", seed: int = 0,
                   information: CodeInformation | None = None, recorded_moves: bool = False) -> Plan:
    """Whole presses up to `budget_s` robot seconds (see the module docstring for the cost; with
    `recorded_moves`, for presses run in recorded order, each pays its recorded lead as its move).

    `spread`: farthest-point order in the press summaries, starting from the press nearest
    their mean (ties broken by a seeded draw); a press whose orientation is new must also
    pay its re-mount. `cover`: `spread` within each subset of the orientations, keeping the
    plan with the smallest covering radius (the largest summary distance from any candidate
    press to the plan's nearest press; fewer orientations on a tie): a re-mount is paid only
    where its orientation reaches targets the others leave far away. `random`: presses in a
    seeded random order. `first`: presses in recorded order (what a budget cut from the start
    of a recorded stream gives, in whole presses). `informative`: within each subset of the
    orientations (its re-mounts paid first), the press of the largest gain in the criterion of
    `information` per robot second, again and again; the subset of the best final criterion is
    kept (fewer orientations on a tie). `cover_informative`: `cover`'s plan, then each of its presses
    exchanged for the press of its cell (the candidates of its orientations nearest it in the press
    summaries) that most improves the criterion within the budget, over the cells in turn until no
    exchange improves it: `cover`'s spread over forces and places, each place's most informative
    press. Each strategy adds presses while the budget allows and skips those it cannot afford.
    """
    if not np.isfinite(budget_s) or budget_s < 0:
        raise AnytipError(f"a calibration budget must be a finite number of seconds >= 0, got {budget_s}")
    if budget_s == 0 or len(presses) == 0:
        return Plan.empty()
    moves = presses.moves(rig, recorded_moves)
    cost = presses.duration_s + moves
    if strategy == "spread":
        chosen = _spread(presses, cost, budget_s, rig.remount_s, seed)
    elif strategy == "cover":
        chosen = _cover(presses, cost, budget_s, rig.remount_s, seed)
    elif strategy == "informative":
        chosen = _informative(presses, cost, budget_s, rig.remount_s, _checked(information, len(presses)))
    elif strategy == "cover_informative":
        information = _checked(information, len(presses))
        start = _cover(presses, cost, budget_s, rig.remount_s, seed)
        chosen = _exchanged(presses, cost, budget_s, rig.remount_s, start, information)
    elif strategy in ("random", "first", "designed"):
        order = (np.random.default_rng(seed).permutation(len(presses)) if strategy == "random"
                 else np.arange(len(presses)))
        chosen = _in_order(presses, cost, order, budget_s, rig.remount_s)
    else:
        raise AnytipError(f"unknown plan strategy {strategy!r}; "
                          "use spread, cover, random, first, designed, informative or cover_informative")
    return _plan(presses, chosen, rig, moves)


def ordinary_use_seed(seed: int, unit: str) -> int:
    """The seed of unit `unit`'s draw of ordinary use under a run's `seed` (the same in every
    process: the unit's id by CRC-32, not Python's salted hash)."""
    return unit_seed(seed, zlib.crc32(unit.encode()), "ordinary use")


def ordinary_use(presses: Presses, seconds: float, seed: int) -> Plan:
    """A unit's ordinary use after mounting, read without labels: whole presses drawn in a seeded
    random order from anywhere among `presses` until `seconds` of contact, so the contacts spread
    over what the presses cover. Ordinary use costs no rig time (no moves, no re-mounts): the
    plan's `calib_seconds` are its `contact_seconds`."""
    return select_presses(presses, seconds, RigTiming(move_s=0.0, remount_s=0.0), "random", seed)


def stream_presses(arrays: FleetArrays, unit: str, stream: CalibrationStream) -> Presses:
    """Every press of a unit's calibration stream `stream` (its other runs left out)."""
    return find_presses(arrays, unit, stream.outside(arrays))


def stream_ordinary_use(arrays: FleetArrays, unit: str, stream: CalibrationStream, seconds: float,
                        seed: int, presses: Presses | None = None) -> Plan:
    """`ordinary_use` of every press of a unit's calibration stream `stream` (`stream_presses`, or
    `presses` where the caller found them), drawn under the run's `seed` and the unit's id
    (`ordinary_use_seed`)."""
    found = stream_presses(arrays, unit, stream) if presses is None else presses
    return ordinary_use(found, seconds, ordinary_use_seed(seed, unit))


def _spread(presses: Presses, cost: np.ndarray, budget_s: float, remount_s: float, seed: int) -> list[int]:
    z = presses.summary
    jitter = np.random.default_rng(seed).random(len(presses)) * 1e-9
    score = -np.linalg.norm(z - z.mean(0), axis=1)  # the first press: nearest the mean
    chosen: list[int] = []
    spent, used = 0.0, set()
    while True:
        extra = np.where(np.isin(presses.orientation_deg, list(used)) | (not used), 0.0, remount_s)
        affordable = spent + cost + extra <= budget_s + 1e-9
        affordable[chosen] = False
        if not affordable.any():
            return chosen
        k = int(np.argmax(np.where(affordable, score + jitter, -np.inf)))
        chosen.append(k)
        spent += cost[k] + extra[k]
        used.add(float(presses.orientation_deg[k]))
        nearest = np.linalg.norm(z - z[k], axis=1)
        score = nearest if len(chosen) == 1 else np.minimum(score, nearest)


def _orientation_subsets(presses: Presses, strategy: str,
                         instead: str = "") -> Iterator[tuple[int, np.ndarray]]:
    """(size, idx) of every subset of the presses' orientations, smallest first: the subset's
    orientation count and the indices (P',) of its presses. More than MAX_COVER_ORIENTATIONS
    orientations are refused naming `strategy` (and what to use `instead`)."""
    orientations = np.unique(presses.orientation_deg)
    if len(orientations) > MAX_COVER_ORIENTATIONS:
        raise AnytipError(f"plan strategy {strategy} tries every subset of at most {MAX_COVER_ORIENTATIONS} "
                          f"orientations; this unit's runs have {len(orientations)}{instead}")
    for size in range(1, len(orientations) + 1):
        for subset in itertools.combinations(orientations, size):
            yield size, np.flatnonzero(np.isin(presses.orientation_deg, subset))


def _cover(presses: Presses, cost: np.ndarray, budget_s: float, remount_s: float, seed: int) -> list[int]:
    z = presses.summary
    best: tuple[float, list[int]] = (np.inf, [])
    for _, idx in _orientation_subsets(presses, "cover", ": use spread"):
        keep = np.zeros(len(presses), bool)
        keep[idx] = True
        chosen = [int(idx[k]) for k in _spread(presses.subset(keep), cost[idx], budget_s, remount_s, seed)]
        if not chosen:
            continue
        gap = float(cKDTree(z[chosen]).query(z)[0].max())
        if gap < best[0] - 1e-12:
            best = (gap, chosen)
    return best[1]


def _checked(information: CodeInformation | None, n_presses: int) -> CodeInformation:
    if information is None:
        raise AnytipError("plan strategies informative and cover_informative choose presses for what they "
                          "tell a response model's codes: they need the response method (options.response)")
    if len(information.per_press) != n_presses:
        raise AnytipError(f"code information for {len(information.per_press)} presses, "
                          f"the unit has {n_presses}")
    if information.criterion not in CRITERIA:
        raise AnytipError(f"unknown plan criterion {information.criterion!r}; use d or v")
    return information


def _informative(presses: Presses, cost: np.ndarray, budget_s: float, remount_s: float,
                 information: CodeInformation) -> list[int]:
    best: tuple[float, list[int]] = (-np.inf, [])
    for size, idx in _orientation_subsets(presses, "informative"):
        chosen, value = _greedy_information(information, idx, cost, budget_s - remount_s * (size - 1))
        if chosen and (not best[1] or value > best[0] + 1e-9 * max(1.0, abs(best[0]))):
            best = (value, chosen)
    return best[1]


def _greedy_information(information: CodeInformation, candidates: np.ndarray, cost: np.ndarray,
                        budget_s: float) -> tuple[list[int], float]:
    """Presses of `candidates` added by the largest gain in the criterion per second of `cost` while
    `budget_s` allows: (the presses, the criterion of the plan)."""
    precision = information.prior.astype(np.float64).copy()
    value = information.value(precision)
    chosen: list[int] = []
    left, spent = candidates, 0.0
    while True:
        left = left[spent + cost[left] <= budget_s + 1e-9]
        if not len(left):
            return chosen, value
        gain = information.values(precision + information.per_press[left]) - value
        k = int(np.argmax(gain / cost[left]))
        pick = int(left[k])
        chosen.append(pick)
        spent += float(cost[pick])
        precision = precision + information.per_press[pick]
        value = float(value + gain[k])
        left = np.delete(left, k)


EXCHANGE_PASSES = 3  # `cover_informative`'s passes over the cells at most


def _cells(presses: Presses, chosen: list[int]) -> np.ndarray:
    """(P,) the cell of every candidate press: the index in `chosen` of the press nearest it in the
    summaries, among candidates of `chosen`'s orientations (-1 for the others)."""
    cell = cKDTree(presses.summary[chosen]).query(presses.summary)[1]
    return np.where(np.isin(presses.orientation_deg, presses.orientation_deg[chosen]), cell, -1)


def _exchanged(presses: Presses, cost: np.ndarray, budget_s: float, remount_s: float, chosen: list[int],
               information: CodeInformation) -> list[int]:
    """`chosen`, each press exchanged in turn for the press of its cell (`select_presses`) that most
    improves the criterion, while the plan's cost stays within `budget_s`."""
    if not chosen:
        return chosen
    chosen = list(chosen)
    cell = _cells(presses, chosen)
    fixed = remount_s * (len(set(presses.orientation_deg[chosen])) - 1)
    precision = information.prior + information.per_press[chosen].sum(0)
    value = information.value(precision)
    for _ in range(EXCHANGE_PASSES):
        moved = False
        for j in range(len(chosen)):
            spare = budget_s - fixed - (cost[chosen].sum() - cost[chosen[j]])
            free = np.ones(len(cell), bool)
            free[chosen] = False
            mates = np.flatnonzero(free & (cell == j) & (cost <= spare + 1e-9))
            if not len(mates):
                continue
            trial = precision - information.per_press[chosen[j]] + information.per_press[mates]
            values = information.values(trial)
            k = int(np.argmax(values))
            if values[k] > value + 1e-9 * max(1.0, abs(value)):
                precision, value, chosen[j], moved = trial[k], float(values[k]), int(mates[k]), True
        if not moved:
            break
    return chosen


def _in_order(presses: Presses, cost: np.ndarray, order: np.ndarray, budget_s: float,
              remount_s: float) -> list[int]:
    chosen: list[int] = []
    spent, used = 0.0, set()
    for k in order:
        o = float(presses.orientation_deg[k])
        c = cost[k] + (remount_s if used and o not in used else 0.0)
        if spent + c <= budget_s + 1e-9:
            chosen.append(int(k))
            spent += c
            used.add(o)
    return chosen


def _plan(presses: Presses, chosen: list[int], rig: RigTiming, moves: np.ndarray) -> Plan:
    """The chosen presses grouped by orientation (in order of first use), priced; moves (P,) s before each."""
    if not chosen:
        return Plan.empty()
    orientations = tuple(dict.fromkeys(float(presses.orientation_deg[k]) for k in chosen))
    ordered = sorted(chosen, key=lambda k: (orientations.index(float(presses.orientation_deg[k])),
                                            chosen.index(k)))
    rows, bounds = _stack([presses.rows_of(k) for k in ordered])
    contact = float(presses.duration_s[ordered].sum())
    seconds = contact + float(moves[ordered].sum()) + rig.remount_s * (len(orientations) - 1)
    return Plan(rows, len(ordered), seconds, contact, orientations,
                min(float(len(rows)), contact * rig.effective_hz), bounds)


@dataclass(frozen=True)
class Budget:
    """One calibration budget: `amount` labeled samples, the first rows of the unit's
    calibration stream (unit "samples"), or `amount` robot seconds of whole presses chosen
    by `strategy` (unit "seconds"). An amount of 0 is label-free."""

    amount: float
    unit: BudgetUnit = "samples"
    strategy: Strategy = "spread"

    @property
    def label(self) -> str:
        if self.unit == "samples":
            return f"{int(self.amount)}"
        return f"{self.amount:g} s" if self.amount == 0 else f"{self.amount:g} s {self.strategy}"


def stream_plan(stream: CalibrationStream, n: int) -> Plan:
    """The first n rows of a calibration stream as a plan (its robot time is the stream's
    clock at the n-th row; every row counts as an effective sample)."""
    rows = stream.first(n)
    return Plan(rows, 0, stream.seconds_for(n), stream.seconds_for(n), (), float(len(rows)),
                np.array([0, len(rows)], np.int64))


def plan_for(budget: Budget, stream: CalibrationStream, presses: Presses, rig: RigTiming = RigTiming(),
             seed: int = 0, information: CodeInformation | None = None,
             designed_s: float | None = None) -> Plan:
    """The labeled rows a budget grants one unit: a stream prefix or a selection of presses.
    Strategy `designed` takes, in recorded order up to the budget, the presses of the unit's runs
    of the designed protocol of `designed_s` robot seconds (default the budget's; `plan<seconds>`,
    sensor.protocols.design_protocol), as a lab that ran the designed plan on the unit would; a
    unit without such runs gets an empty plan."""
    if budget.unit == "samples":
        return stream_plan(stream, int(budget.amount))
    if budget.strategy == "designed":
        design = budget.amount if designed_s is None else designed_s
        mine = presses.subset(presses.protocol == designed_name(design))
        return select_presses(mine, budget.amount, rig, "first", seed, recorded_moves=True)
    return select_presses(presses, budget.amount, rig, budget.strategy, seed, information)


def _rows_of_runs(arrays: FleetArrays, protocol_is: Callable[[str | None], bool]) -> np.ndarray:
    """(N,) bool: rows of the runs whose protocol `protocol_is` holds for."""
    return np.isin(arrays.run, [k for k, r in enumerate(arrays.runs) if protocol_is(r.protocol)])


def designed_rows(arrays: FleetArrays) -> np.ndarray:
    """(N,) bool: rows of runs of a designed calibration (`plan<seconds>`, `is_designed`)."""
    return _rows_of_runs(arrays, is_designed)


def test_session_rows(arrays: FleetArrays) -> np.ndarray:
    """(N,) bool: rows of runs of a unit's test session (`retest`, `is_test_session`)."""
    return _rows_of_runs(arrays, is_test_session)


def designed_name(seconds: float) -> str:
    """The protocol name of the designed calibration of `seconds` robot seconds."""
    return f"plan{seconds:g}"


def plan_points(sensor_model: str | None, points: str | None = None) -> str:
    """`points`, else the designed plan's default points of `sensor_model` (None: the fingertip):
    drawn at random on a flat design (`sensor.flat.DEFAULT_PLAN_POINTS`), the low-discrepancy order
    on the fingertip (PLAN_POINTS[0])."""
    if points is not None:
        return points
    return flat.DEFAULT_PLAN_POINTS if sensor_model in flat.DESIGNS else PLAN_POINTS[0]


def designed_plan_csv(seconds: float, rig: RigTiming = RigTiming(), seed: int = 0,
                      sensor_model: str | None = None, points: str | None = None
                      ) -> tuple[str, float, str]:
    """The designed calibration of `seconds` robot seconds as robot waypoints in CSV, the plan's
    robot time in seconds, re-mounts included, and what it presses in words; `points` None takes the
    sensor's default (`plan_points`). The fingertip's (default, `sensor.protocols.design_protocol` of
    `points`): columns WAYPOINT_COLUMNS (docs/cross_sensor.md). A flat design's (`sensor_model` in
    `sensor.flat.DESIGNS`, `sensor.flat.design_plan` of `points`): stage waypoints
    (`sensor.flat.plan_waypoints`), one orientation."""
    if sensor_model is not None:
        design = flat.get_design(sensor_model)
        plan = flat.design_plan(design, seconds, rig.move_s, seed, plan_points(sensor_model, points))
        columns, table = flat.plan_waypoints(design, plan)
        n = len(plan.level)
        what = f"{n} presses, one at each of {n} places, on 1 orientation"
        return _csv(columns, table, ".6f"), plan.duration_s, what
    protocol = design_protocol(seconds, rig.move_s, rig.remount_s, plan_points(None, points))
    table = waypoints(protocol, rig.remount_s, np.random.default_rng(seed))
    total = protocol.duration_s + rig.remount_s * (len(protocol.orientations_deg) - 1)
    return _csv(WAYPOINT_COLUMNS, table, ".4f"), total, press_summary(protocol)


def _csv(columns: tuple[str, ...], table: np.ndarray, fmt: str) -> str:
    lines = [",".join(columns)] + [",".join(format(v, fmt) for v in row) for row in table]
    return "\n".join(lines) + "\n"
