"""Splits: units into train / validation / held-out roles, rows into the paper's random
split and into held-out patches. Everything is deterministic from a seed.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass

import numpy as np

from anytip.data.seeds import TEST_PATCHES, stream_seed
from anytip.errors import AnytipError


@dataclass(frozen=True)
class UnitSplit:
    """Unit roles; no unit is in two roles. `factor`: units that only learn how wide a held-out
    unit's intervals must be, beside the validation units (none unless asked for)."""

    train: tuple[str, ...]
    val: tuple[str, ...]
    test: tuple[str, ...]
    factor: tuple[str, ...] = ()

    def to_json(self) -> dict[str, list[str]]:
        """Each role's units; `factor` only where there are any (a split without them reads as before)."""
        return {k: list(v) for k, v in asdict(self).items() if k != "factor" or v}


def split_units(units: Sequence[str], seed: int, n_val: int, n_test: int,
                n_train: int | None = None, folds: int | None = None, n_factor: int = 0) -> UnitSplit:
    """Shuffle `units` with `seed` and deal held-out, then validation, then training units.

    `n_train` None takes every remaining unit. With `folds` K the held-out units are fold
    seed % K of one fixed shuffle instead (every unit is held out once over seeds 0..K-1, and
    `n_test` is ignored); validation and training units are dealt from the rest with `seed`.
    `n_factor` units are dealt after the training units (so the other roles stay as they are
    without them) as factor units; it needs `n_train`. Raises if the registry holds too few.
    """
    units = sorted(set(units))
    if n_factor and n_train is None:
        raise AnytipError(f"{n_factor} factor units are dealt after the training units: the split needs "
                          "n_train_units")
    if folds is not None:
        return _fold_split(units, seed, n_val, n_train, folds, n_factor)
    need = n_val + n_test + (n_train or 1) + n_factor
    if len(units) < need:
        raise AnytipError(
            f"the registry holds {len(units)} units of this sensor model; the split needs "
            f"at least {need} ({n_test} held-out, {n_val} validation, {n_train or '>= 1'} training"
            f"{f', {n_factor} factor' if n_factor else ''})"
        )
    order = [units[i] for i in np.random.default_rng(seed).permutation(len(units))]
    test = order[:n_test]
    return _deal_rest(order[n_test:], test, n_val, n_train, n_factor)


def _fold_split(units: list[str], seed: int, n_val: int, n_train: int | None, folds: int,
                n_factor: int = 0) -> UnitSplit:
    if not 2 <= folds <= len(units):
        raise AnytipError(f"unit folds: {folds} folds need 2 to {len(units)} units' worth; the registry "
                          f"holds {len(units)} units")
    order = [units[i] for i in np.random.default_rng(0).permutation(len(units))]
    test = order[seed % folds::folds]
    rest = [u for u in units if u not in test]
    if len(rest) < n_val + (n_train or 1) + n_factor:
        raise AnytipError(f"fold {seed % folds} holds out {len(test)} of {len(units)} units, leaving "
                          f"{len(rest)}; the split needs {n_val} validation, {n_train or '>= 1'} training"
                          f"{f' and {n_factor} factor' if n_factor else ''}")
    return _deal_rest([rest[i] for i in np.random.default_rng(seed).permutation(len(rest))], test, n_val,
                      n_train, n_factor)


def _deal_rest(rest: list[str], test: list[str], n_val: int, n_train: int | None, n_factor: int) -> UnitSplit:
    """Validation, then training, then factor units from the shuffled units left after the held-out ones."""
    val = rest[:n_val]
    train = rest[n_val:] if n_train is None else rest[n_val:n_val + n_train]
    factor = rest[n_val + len(train):n_val + len(train) + n_factor]
    return UnitSplit(tuple(sorted(train)), tuple(sorted(val)), tuple(sorted(test)), tuple(sorted(factor)))


def random_rows(n_rows: int, test_fraction: float, seed: int) -> np.ndarray:
    """The paper's split: (n_rows,) bool, True for a random `test_fraction` of rows."""
    rng = np.random.default_rng(seed)
    mask = np.zeros(n_rows, bool)
    mask[rng.choice(n_rows, size=int(round(test_fraction * n_rows)), replace=False)] = True
    return mask


def held_out_patches(patch: np.ndarray, test_fraction: float, seed: int) -> np.ndarray:
    """(N,) bool, True for rows of whole patches held out from training.

    A `test_fraction` of the distinct patch cells (at least one, at most all but one)
    is chosen at random; every row of a chosen patch is a test row.
    """
    cells = np.unique(patch)
    if len(cells) < 2:
        raise AnytipError(f"held-out patches need at least 2 patches; the rows cover {len(cells)}")
    k = int(np.clip(round(test_fraction * len(cells)), 1, len(cells) - 1))
    chosen = np.random.default_rng(seed).choice(cells, size=k, replace=False)
    return np.isin(patch, chosen)


TestMask = Callable[[np.ndarray, int], np.ndarray]


def patch_test_mask(fraction: float, seed: int) -> TestMask:
    """Held-out whole patches; each unit draws its own patches (seed, unit index)."""
    return lambda patch, u: held_out_patches(patch, fraction, stream_seed(TEST_PATCHES, seed, u))


def random_test_mask(fraction: float, seed: int) -> TestMask:
    """The paper's random rows."""
    return lambda patch, u: random_rows(len(patch), fraction, stream_seed(TEST_PATCHES, seed, u))
