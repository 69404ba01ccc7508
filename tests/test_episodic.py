"""Episodic shared training (train/episodic.py): episodes are whole presses, the query never
sees them, and the query loss reaches the shared weights through the inner fit."""

import numpy as np
import pytest
import torch

from anytip.errors import AnytipError
from anytip.models.adapted import AdaptedMLP
from anytip.models.mlp import MLPConfig
from anytip.train.adapt import input_stats, train_shared
from anytip.train.data import FleetBatchData, UnitTensors
from anytip.train.episodic import EpisodeRecipe, PressIndex, episode_loss, inner_fit, inner_rates
from anytip.train.recipe import TrainRecipe


def _index(rng: np.random.Generator, presses=(6, 9, 4), rows=(50, 70, 30)) -> tuple[PressIndex, list]:
    ids = [np.sort(rng.integers(0, p, n)) * 7 + 3 for p, n in zip(presses, rows, strict=True)]
    return PressIndex.from_ids(ids, max(rows), "cpu"), ids


def test_support_is_whole_chosen_presses_and_the_query_excludes_them():
    rng = np.random.default_rng(0)
    index, ids = _index(rng)
    recipe = EpisodeRecipe(presses=10, rows_per_press=5)
    g = torch.Generator().manual_seed(1)
    for _ in range(20):
        rows, chosen = index.draw(recipe, g)
        K = int(index.n_presses.min()) - 1  # 10 asked, the fewest presses keep one for the query
        assert chosen.shape == (3, K) and rows.shape == (3, K * 5)
        for u in range(3):
            assert len(set(chosen[u].tolist())) == K
            assert int(chosen[u].max()) < int(index.n_presses[u])
            of = index.press[u, rows[u]].view(K, 5)
            assert (of == chosen[u][:, None]).all()  # each press's rows come from that press
            assert int(rows[u].max()) < len(ids[u])  # never a padding row
        batch = torch.randint(0, 30, (3, 40), generator=g)
        keep = index.outside(batch, chosen)
        inside = (index.press.gather(1, batch)[:, :, None] == chosen[:, None, :]).any(-1)
        assert torch.equal(keep.bool(), ~inside)


def test_a_unit_with_one_press_is_refused():
    with pytest.raises(AnytipError, match="at least 2 presses"):
        PressIndex.from_ids([np.zeros(10, int), np.arange(10)], 10, "cpu")


def test_the_query_loss_reaches_shared_weights_and_step_sizes():
    torch.manual_seed(0)
    model = AdaptedMLP(3, MLPConfig(sizes=(8, 16, 16, 5)), "input_affine+film")
    index, _ = _index(np.random.default_rng(1))
    X, Y = torch.randn(3, 70, 8), torch.randn(3, 70, 5)
    recipe = EpisodeRecipe(presses=2, rows_per_press=4, inner_steps=3)
    rates = inner_rates(model, recipe)
    loss = episode_loss(model, X, Y, index, torch.randint(0, 30, (3, 32)), rates, recipe,
                        torch.Generator().manual_seed(0))
    loss.backward()
    assert all(w.grad is not None and w.grad.abs().sum() > 0 for w in model.weights)
    assert all(r.grad is not None and r.grad != 0 for r in rates.values())
    assert all(p.grad is None for p in model.adapter_parameters())  # episodes fit their own adapters


def test_train_shared_with_episodes_learns_step_sizes_and_refuses_heteroscedastic_heads():
    g = torch.Generator().manual_seed(0)
    units = [UnitTensors(torch.randn(60, 8, generator=g), torch.randn(60, 5, generator=g),
                         torch.randn(10, 8, generator=g), torch.randn(10, 5, generator=g), f"u{k}")
             for k in range(3)]
    data = FleetBatchData.from_units(units)
    stats = input_stats([data.X_train[u, : int(data.n_train[u])] for u in range(data.n_units)])
    index = PressIndex.from_ids([np.arange(60) // 10] * 3, 60, "cpu")
    recipe = TrainRecipe(name="t", epochs=2, batch_size=16)
    fit = train_shared(data, stats, MLPConfig(sizes=(8, 8, 5)), "film", recipe, seed=0,
                       episodes=(EpisodeRecipe(presses=2, rows_per_press=4), index))
    rates = fit.history[-1]["inner_lr"]
    assert set(rates) == set(fit.model.adapter.keys()) and any(abs(r - 0.1) > 1e-4 for r in rates.values())
    with pytest.raises(AnytipError, match="episodic training needs"):
        train_shared(data, stats, MLPConfig(sizes=(8, 8, 5)), "film", TrainRecipe(name="t", epochs=1),
                     seed=0, hetero_beta=0.5, episodes=(EpisodeRecipe(), index))


def test_the_inner_fit_lowers_each_models_loss_and_needs_every_step_size():
    torch.manual_seed(0)
    model = AdaptedMLP(2, MLPConfig(sizes=(8, 16, 5)), "input_affine+film")
    X, Y = torch.randn(2, 40, 8), torch.randn(2, 40, 5)
    n = torch.tensor([40, 0])
    before = ((model(X) - Y) ** 2).mean(dim=(1, 2))
    inner_fit(model, X, Y, n, {k: 0.05 for k in model.adapter.keys()}, steps=20)
    after = ((model(X) - Y) ** 2).mean(dim=(1, 2))
    assert after[0] < before[0]
    assert torch.equal(model.adapter["in_A"][1], torch.eye(8))  # no rows: the identity stays
    with pytest.raises(AnytipError, match="no step size"):
        inner_fit(model, X, Y, n, {"in_A": 0.1}, steps=1)


def test_episodes_of_some_units_per_step_reach_only_their_query():
    torch.manual_seed(0)
    model = AdaptedMLP(3, MLPConfig(sizes=(8, 16, 5)), "film")
    index, _ = _index(np.random.default_rng(2))
    X, Y = torch.randn(3, 70, 8), torch.randn(3, 70, 5)
    recipe = EpisodeRecipe(presses=2, rows_per_press=4, inner_steps=2, units_per_step=1)
    X.requires_grad_(True)
    loss = episode_loss(model, X, Y, index, torch.randint(0, 30, (3, 32)), inner_rates(model, recipe), recipe,
                        torch.Generator().manual_seed(0))
    (grad,) = torch.autograd.grad(loss, X)
    assert int((grad.abs().sum(dim=(1, 2)) > 0).sum()) == 1  # one unit's rows took part
