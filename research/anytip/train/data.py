"""The tensors a trainer consumes: every unit's train and validation rows on one device.

Units have different row counts, so each role is padded to (U, N_max, d) and the first
n[u] rows of unit u are real. Nothing here reads files: `data/` builds these.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass

import numpy as np
import torch
from torch import Tensor

from anytip.data.arrays import OUTPUT_NAMES, FleetArrays
from anytip.data.seeds import unit_seed

ArrayLike = Tensor | np.ndarray


@dataclass
class UnitTensors:
    """One unit's rows. X (n, 8) tared pressures in Pa; Y (n, 5) = (Fx, Fy, Fz) N, (theta, phi) rad."""

    X_train: Tensor
    Y_train: Tensor
    X_val: Tensor
    Y_val: Tensor
    unit_id: str = ""


@dataclass
class FleetBatchData:
    """All units, padded: X_* (U, N, d_in), Y_* (U, N, d_out) float32, n_* (U,) int64 real rows.

    The validation rows are what trainers use for early stopping and model selection.
    """

    X_train: Tensor
    Y_train: Tensor
    n_train: Tensor
    X_val: Tensor
    Y_val: Tensor
    n_val: Tensor
    unit_ids: list[str]
    output_names: tuple[str, ...] = OUTPUT_NAMES

    @classmethod
    def from_units(cls, units: Sequence[UnitTensors], device: torch.device | str = "cpu",
                   output_names: Sequence[str] = OUTPUT_NAMES) -> FleetBatchData:
        """Pad and stack per-unit tensors (numpy arrays are accepted too) onto `device`."""
        if not units:
            raise ValueError("no units given")
        ids = [u.unit_id or str(i) for i, u in enumerate(units)]
        for u, uid in zip(units, ids, strict=True):
            _check_unit(u, uid)
        X_train, n_train = pad_rows([u.X_train for u in units], device)
        Y_train, _ = pad_rows([u.Y_train for u in units], device)
        X_val, n_val = pad_rows([u.X_val for u in units], device)
        Y_val, _ = pad_rows([u.Y_val for u in units], device)
        return cls(X_train, Y_train, n_train, X_val, Y_val, n_val, ids, tuple(output_names))

    @property
    def n_units(self) -> int:
        return self.X_train.shape[0]

    @property
    def device(self) -> torch.device:
        return self.X_train.device

    def unit(self, u: int) -> UnitTensors:
        """Unit u's real rows (views, no padding)."""
        nt, nv = int(self.n_train[u]), int(self.n_val[u])
        return UnitTensors(self.X_train[u, :nt], self.Y_train[u, :nt], self.X_val[u, :nv],
                           self.Y_val[u, :nv], self.unit_ids[u])

    def subset(self, units: Sequence[int]) -> FleetBatchData:
        """A fleet of only the given unit indices."""
        return FleetBatchData.from_units([self.unit(u) for u in units], self.device,
                                         self.output_names)

    def to(self, device: torch.device | str) -> FleetBatchData:
        t = [getattr(self, k).to(device) for k in
             ("X_train", "Y_train", "n_train", "X_val", "Y_val", "n_val")]
        return FleetBatchData(*t, list(self.unit_ids), self.output_names)


def pad_rows(rows: Sequence[ArrayLike], device: torch.device | str = "cpu") -> tuple[Tensor, Tensor]:
    """[(n_u, d), ...] -> zero-padded (U, max n_u, d) float32 and counts (U,) int64."""
    ts = [torch.as_tensor(r, dtype=torch.float32, device=device) for r in rows]
    counts = torch.tensor([len(t) for t in ts], dtype=torch.int64, device=device)
    out = torch.zeros(len(ts), int(counts.max()), ts[0].shape[1], device=device)
    for u, t in enumerate(ts):
        out[u, : len(t)] = t
    return out, counts


def split_rows(X: ArrayLike, Y: ArrayLike, val_fraction: float = 0.1, seed: int = 0,
               unit_id: str = "") -> UnitTensors:
    """The paper's random row split of one unit into train and validation rows.

    Random rows beside training rows are optimistic as a test set; use it for model
    selection, and evaluate on held-out patches or time blocks.
    """
    X, Y = torch.as_tensor(X, dtype=torch.float32), torch.as_tensor(Y, dtype=torch.float32)
    n_val = max(1, round(val_fraction * len(X)))
    perm = torch.randperm(len(X), generator=torch.Generator().manual_seed(seed))
    val, train = perm[:n_val], perm[n_val:]
    return UnitTensors(X[train], Y[train], X[val], Y[val], unit_id)


class UnitSampler:
    """Per-epoch row orders for every unit, drawn on the data's device.

    Each unit has its own generator, so unit u's draws depend only on the seed, u, its own
    row count and the epoch length: never on another unit's data. An epoch is
    ceil(max_u n_u / B) steps; a unit with fewer rows walks through more than one shuffled
    pass of its rows in that time.
    """

    def __init__(self, n_rows: Tensor, batch_size: int, seed: int, device: torch.device):
        self.n = [int(n) for n in n_rows]
        self.batch_size = batch_size
        self.steps_per_epoch = math.ceil(max(self.n) / batch_size)
        self.device = device
        self.generators = [torch.Generator(device).manual_seed(unit_seed(seed, u, "sample"))
                           for u in range(len(self.n))]

    def epoch(self) -> Tensor:
        """Row indices (steps_per_epoch, U, B), int64, into each unit's padded rows."""
        length = self.steps_per_epoch * self.batch_size
        orders = []
        for n, g in zip(self.n, self.generators, strict=True):
            passes = [torch.randperm(n, generator=g, device=self.device)
                      for _ in range(math.ceil(length / n))]
            orders.append(torch.cat(passes)[:length])
        U = len(self.n)
        return torch.stack(orders).view(U, self.steps_per_epoch, self.batch_size).transpose(0, 1)

    def steps(self, total: int) -> Iterator[tuple[int, Tensor]]:
        """(step, row indices (U, B)) for `total` steps, drawing a new epoch order as each ends."""
        for step in range(total):
            if step % self.steps_per_epoch == 0:
                order = self.epoch()
            yield step, order[step % self.steps_per_epoch]

    def stretches(self, total: int, ends: Iterable[int], *tables: Tensor
                  ) -> Iterator[tuple[int, int, list[Tensor]]]:
        """(start, stop, [each table's rows of steps start..stop-1 (stop - start, U, B, ...)]) over
        `total` steps, from tables (U, n_max, ...): stretches that end after each in-epoch step count
        of `ends` (1..steps_per_epoch), at each epoch's end and at `total`; the rows `steps` draws,
        gathered one epoch at a time (one gather per epoch instead of one per step, a seventh of a tiny
        network's step on a CPU; an epoch of rows is held as a second copy of the tables;
        `index_select` on the flattened tables, a quarter of advanced indexing's time)."""
        U, S = len(self.n), self.steps_per_epoch
        offsets = torch.arange(U, device=self.device)[:, None] * tables[0].shape[1]  # each unit's first row
        cuts = sorted({e for e in ends if 0 < e < S} | {S})
        for first in range(0, total, S):
            flat = (self.epoch() + offsets).reshape(-1)  # (S * U * B,) into the (U * n_max) rows
            epoch = [t.reshape(U * t.shape[1], *t.shape[2:]).index_select(0, flat)
                     .view(S, U, self.batch_size, *t.shape[2:]) for t in tables]
            start = first
            for cut in cuts:
                stop = min(first + cut, total)
                if stop > start:
                    yield start, stop, [e[start - first:stop - first] for e in epoch]
                    start = stop


def _check_unit(u: UnitTensors, uid: str) -> None:
    for role, X, Y in (("train", u.X_train, u.Y_train), ("val", u.X_val, u.Y_val)):
        if len(X) == 0:
            raise ValueError(f"unit {uid}: no {role} rows")
        if len(X) != len(Y):
            raise ValueError(f"unit {uid}: {len(X)} X_{role} rows but {len(Y)} Y_{role} rows")


def split_validation(rows: np.ndarray, fraction: float,
                     rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """(fitting rows, validation rows): a random `fraction` of `rows`, at least one, validates."""
    is_val = np.zeros(len(rows), bool)
    is_val[rng.choice(len(rows), max(1, round(fraction * len(rows))), replace=False)] = True
    return rows[~is_val], rows[is_val]


def unit_tensors(arrays: FleetArrays, fit_rows: np.ndarray, val_rows: np.ndarray,
                 unit: str) -> UnitTensors:
    """One unit's fitting and validation rows of `arrays` as trainer tensors."""
    t = arrays.targets
    return UnitTensors(torch.from_numpy(arrays.pressure[fit_rows]), torch.from_numpy(t[fit_rows]),
                       torch.from_numpy(arrays.pressure[val_rows]), torch.from_numpy(t[val_rows]), unit)
