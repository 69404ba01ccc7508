import numpy as np
import pytest
import torch

from anytip.train import FleetBatchData, UnitSampler, UnitTensors, pad_rows, split_rows
from anytip.train.synthetic import synthetic_fleet


def _unit(n_train, n_val, uid=""):
    return UnitTensors(torch.randn(n_train, 8), torch.randn(n_train, 5), torch.randn(n_val, 8),
                       torch.randn(n_val, 5), uid)


def test_from_units_pads_and_unit_gives_back_the_rows():
    units = [_unit(30, 5, "a"), _unit(50, 7, "b"), _unit(10, 2)]
    data = FleetBatchData.from_units(units)
    assert data.X_train.shape == (3, 50, 8) and data.Y_val.shape == (3, 7, 5)
    assert data.n_train.tolist() == [30, 50, 10] and data.unit_ids == ["a", "b", "2"]
    for u, unit in enumerate(units):
        assert torch.equal(data.unit(u).X_train, unit.X_train)
        assert torch.equal(data.unit(u).Y_val, unit.Y_val)
    assert (data.X_train[2, 10:] == 0).all()
    sub = data.subset([1])
    assert sub.n_units == 1 and sub.unit_ids == ["b"] and sub.X_train.shape == (1, 50, 8)


def test_from_units_accepts_numpy_and_refuses_bad_units():
    u = UnitTensors(np.zeros((4, 8)), np.zeros((4, 5)), np.zeros((2, 8)), np.zeros((2, 5)))
    assert FleetBatchData.from_units([u]).X_train.dtype == torch.float32
    with pytest.raises(ValueError, match="unit x: no val rows"):
        FleetBatchData.from_units([_unit(5, 0, "x")])
    with pytest.raises(ValueError, match="4 X_train rows but 3"):
        FleetBatchData.from_units([UnitTensors(torch.zeros(4, 8), torch.zeros(3, 5),
                                               torch.zeros(1, 8), torch.zeros(1, 5), "y")])


def test_pad_rows_and_split_rows():
    padded, n = pad_rows([torch.ones(2, 3), torch.ones(4, 3)])
    assert padded.shape == (2, 4, 3) and n.tolist() == [2, 4] and padded[0, 2:].sum() == 0
    X, Y = torch.arange(100.0).view(50, 2), torch.arange(50.0).view(50, 1)
    s = split_rows(X, Y, val_fraction=0.2, seed=1, unit_id="u")
    assert len(s.X_val) == 10 and len(s.X_train) == 40
    rows = torch.cat([s.Y_train, s.Y_val]).flatten().sort().values
    assert torch.equal(rows, Y.flatten())
    assert torch.equal(s.X_train[:, 0], 2 * s.Y_train[:, 0])


def test_sampler_covers_each_units_rows_every_epoch():
    sampler = UnitSampler(torch.tensor([40, 15, 32]), batch_size=8, seed=0, device=torch.device("cpu"))
    order = sampler.epoch()
    assert order.shape == (5, 3, 8)  # ceil(40 / 8) steps
    for u, n in enumerate([40, 15, 32]):
        drawn = order[:, u].flatten()
        assert drawn.max() < n and set(drawn.tolist()) == set(range(n))
    assert not torch.equal(order, sampler.epoch())


def test_sampler_draws_per_unit_streams():
    """Unit 0's draws are the same whatever the other units' row counts (same epoch length)."""
    a = UnitSampler(torch.tensor([40, 10]), 8, seed=3, device=torch.device("cpu")).epoch()
    b = UnitSampler(torch.tensor([40, 25, 7]), 8, seed=3, device=torch.device("cpu")).epoch()
    assert torch.equal(a[:, 0], b[:, 0])


def test_synthetic_fleet_is_seeded_and_physical():
    a, b = synthetic_fleet(2, 500, seed=4), synthetic_fleet(2, 500, seed=4)
    assert torch.equal(a.X_train, b.X_train)
    assert a.X_train.shape == (2, 450, 8) and a.n_val.tolist() == [50, 50]
    assert 1e3 < a.X_train.abs().max() < 2e5  # Pa
    assert a.Y_train[..., 2].min() > 0  # Fz pushes in


def test_stretches_are_the_rows_steps_draws_and_end_where_asked():
    """Gathering an epoch at once hands each step the rows `steps` names for it; stretches end after the
    in-epoch steps asked, at each epoch's end (5 steps here) and at the last step."""
    n = torch.tensor([40, 15, 32])
    X = torch.randn(3, 40, 2)
    Y = torch.arange(120.0).view(3, 40, 1)
    a = UnitSampler(n, batch_size=8, seed=4, device=torch.device("cpu"))
    b = UnitSampler(n, batch_size=8, seed=4, device=torch.device("cpu"))
    rows_of = torch.arange(3)[:, None]
    steps = list(a.steps(12))  # two epochs and a bit
    stretches = list(b.stretches(12, {2, 9}, X, Y))
    assert [(start, stop) for start, stop, _ in stretches] == [(0, 2), (2, 5), (5, 7), (7, 10), (10, 12)]
    drawn = [(x, y) for _, _, (xs, ys) in stretches for x, y in zip(xs.unbind(0), ys.unbind(0), strict=True)]
    for (_, idx), (x, y) in zip(steps, drawn, strict=True):
        assert x.shape == (3, 8, 2) and y.shape == (3, 8, 1)
        assert torch.equal(x, X[rows_of, idx]) and torch.equal(y, Y[rows_of, idx])
