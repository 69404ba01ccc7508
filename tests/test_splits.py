"""Splits: units in one role only, held-out patches whole, deterministic from the seed."""

import numpy as np
import pytest

from anytip.data.splits import held_out_patches, random_rows, split_units
from anytip.errors import AnytipError

UNITS = [f"U{i:02d}" for i in range(12)]


def test_split_units_disjoint_and_deterministic():
    a = split_units(UNITS, seed=3, n_val=2, n_test=3)
    assert a == split_units(list(reversed(UNITS)), seed=3, n_val=2, n_test=3)
    assert a != split_units(UNITS, seed=4, n_val=2, n_test=3)
    roles = [set(a.train), set(a.val), set(a.test)]
    assert sum(len(r) for r in roles) == 12 and set().union(*roles) == set(UNITS)
    assert (len(a.test), len(a.val)) == (3, 2)


def test_split_units_too_few_says_so():
    with pytest.raises(AnytipError, match="holds 3 units"):
        split_units(UNITS[:3], seed=0, n_val=2, n_test=2)


def test_held_out_patches_are_whole():
    patch = np.repeat(np.arange(10), 50)
    test = held_out_patches(patch, 0.3, seed=1)
    assert set(np.unique(patch[test])).isdisjoint(np.unique(patch[~test]))
    assert len(np.unique(patch[test])) == 3


def test_random_rows_fraction():
    mask = random_rows(1000, 0.1, seed=0)
    assert mask.sum() == 100
    np.testing.assert_array_equal(mask, random_rows(1000, 0.1, seed=0))


def test_unit_folds_hold_out_every_unit_exactly_once():
    units = [f"U{k:02d}" for k in range(16)]
    held = []
    for seed in range(4):
        split = split_units(units, seed, n_val=2, n_test=99, folds=4)
        assert len(split.test) == 4 and len(split.val) == 2 and len(split.train) == 10
        assert not set(split.test) & set(split.val) and not set(split.test) & set(split.train)
        held += split.test
    assert sorted(held) == units
    assert split_units(units, 5, 2, 0, folds=4) == split_units(units, 5, 2, 0, folds=4)
    with pytest.raises(AnytipError, match="folds"):
        split_units(units[:3], 0, 1, 1, folds=4)
    with pytest.raises(AnytipError, match="leaving"):
        split_units(units[:4], 0, 3, 1, folds=2)


def test_factor_units_come_after_the_training_units_and_leave_the_other_roles_as_they_were():
    units = [f"U{k:02d}" for k in range(16)]
    for folds in (None, 4):
        plain = split_units(units, 1, n_val=2, n_test=3, n_train=5, folds=folds)
        more = split_units(units, 1, n_val=2, n_test=3, n_train=5, folds=folds, n_factor=3)
        assert (more.train, more.val, more.test) == (plain.train, plain.val, plain.test)
        assert len(more.factor) == 3 and not set(more.factor) & {*more.train, *more.val, *more.test}
        assert "factor" in more.to_json() and "factor" not in plain.to_json()
    with pytest.raises(AnytipError, match="needs n_train_units"):
        split_units(units, 1, n_val=2, n_test=3, n_factor=3)
    with pytest.raises(AnytipError, match="3 factor"):
        split_units(units, 1, n_val=2, n_test=3, n_train=9, n_factor=3)
