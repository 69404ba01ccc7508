"""Shared network with per-unit adapters: identity start, exact folding, few-shot fitting."""

import numpy as np
import pytest
import torch

from anytip.deploy.rounding import check, export_tolerance
from anytip.errors import AnytipError
from anytip.models.adapted import PARTS, AdaptedMLP, parse_kind
from anytip.models.mlp import MLPConfig
from anytip.models.scaler import Scaler
from anytip.train.adapt import AdapterRecipe, SharedFit, fit_adapters, input_stats, train_shared
from anytip.train.data import FleetBatchData, UnitTensors
from anytip.train.recipe import TrainRecipe

KINDS = ["none", "input_affine", "input_diag", "embedding", "film", "input_affine+embedding+film",
         "input_diag+film", "delta", "input_affine+film+delta", "lowrank1", "input_affine+film+lowrank3"]


def randomise(model: AdaptedMLP, seed: int = 0) -> AdaptedMLP:
    g = torch.Generator().manual_seed(seed)
    with torch.no_grad():
        for p in model.adapter.values():
            p.add_(0.3 * torch.randn(p.shape, generator=g))
    return model


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("activation", ["relu", "hardswish"])
def test_fold_equals_adapted_model(kind, activation):
    """The folded network in float32 lies within its float32 rounding bound (as exports are
    verified, deploy/rounding.py) of the adapted model evaluated in float64."""
    config = MLPConfig(activation=activation)
    model = randomise(AdaptedMLP(4, config, kind, seed=3)).double()
    x = torch.randn(4, 200, 8, dtype=torch.float64) * 2
    exact = model(x).detach().numpy()
    folded = model.fold()
    assert folded.config == config and folded.n_models == 4
    last = len(folded.weights) - 1
    params = [(W.detach().numpy().copy(), b.detach().numpy()[:, 0].copy())
              for W, b in zip(folded.weights, folded.biases, strict=True)]
    y32 = folded.float()(x.float()).detach().numpy()
    for m in range(4):
        layers = [(W[m], b[m], activation if k < last else None) for k, (W, b) in enumerate(params)]
        assert check(y32[m], exact[m], export_tolerance(layers, x[m].numpy()), np.ones(5))["passed"]


def test_fold_of_chosen_units():
    model = randomise(AdaptedMLP(5, MLPConfig(), "input_affine+film"))
    x = torch.randn(5, 30, 8)
    torch.testing.assert_close(model.fold([3, 1])(x[[3, 1]]), model(x)[[3, 1]], atol=1e-5, rtol=1e-5)


def test_identity_adapter_changes_nothing():
    bare = AdaptedMLP(3, MLPConfig(), "none", seed=1)
    adapted = AdaptedMLP(3, MLPConfig(), "input_affine+embedding+film", seed=1)
    x = torch.randn(3, 10, 8)
    torch.testing.assert_close(adapted(x), bare(x))
    assert float(adapted.deviation().detach().abs().max()) == 0.0
    assert float(randomise(adapted).deviation().detach().min()) > 0


def test_adapter_sizes():
    sizes = {k: AdaptedMLP(1, MLPConfig(), k.replace("<r>", "2")).n_adapter_params() for k in PARTS}
    widths = MLPConfig().sizes
    lowrank2 = sum(2 * (i + o) + o for i, o in zip(widths[:-1], widths[1:], strict=True))
    assert sizes == {"input_affine": 72, "input_diag": 16, "embedding": 12,
                     "film": 2 * (12 + 64 + 64), "delta": MLPConfig().n_params, "lowrank<r>": lowrank2}


def test_lowrank_change_has_its_rank():
    model = randomise(AdaptedMLP(2, MLPConfig(), "lowrank2"))
    bare = model.fold()
    shared = [w.detach() for w in model.weights]
    for k, W in enumerate(shared):
        change = bare.weights[k][1] - W  # unit 1's change of layer k, (in, out)
        assert int(torch.linalg.matrix_rank(change, atol=1e-5)) == 2


@pytest.mark.parametrize("kind", ["film+nope", "input_affine+input_diag", "lowrank0", "delta+lowrank2",
                                  "lowrank1+lowrank2"])
def test_bad_kind_is_refused(kind):
    with pytest.raises(AnytipError, match="adapter kind"):
        parse_kind(kind)


def fleet(n_units: int, rows: int, seed: int) -> tuple[list[torch.Tensor], list[torch.Tensor]]:
    """Units that see one nonlinear function through a different gain per channel."""
    g = torch.Generator().manual_seed(seed)
    W = torch.randn(4, 3, generator=g)
    Xs, Ys = [], []
    for _ in range(n_units):
        gain = torch.exp(0.5 * torch.randn(4, generator=g))
        z = torch.randn(rows, 4, generator=g)
        Xs.append(z * gain)
        Ys.append(torch.tanh(z @ W))
    return Xs, Ys


def test_adapters_fit_a_new_unit_better_than_the_bare_shared_net():
    torch.manual_seed(0)
    Xs, Ys = fleet(7, 1500, seed=5)
    data = FleetBatchData.from_units(
        [UnitTensors(x[:1200], y[:1200], x[1200:], y[1200:], f"u{i}") for i, (x, y) in
         enumerate(zip(Xs[:6], Ys[:6], strict=True))], output_names=("a", "b", "c"))
    config = MLPConfig(sizes=(4, 16, 16, 3), activation="tanh")
    recipe = TrainRecipe(name="t", lr=1e-2, batch_size=64, epochs=6, schedule="onecycle",
                         warmup_frac=0.1)
    shared = train_shared(data, Scaler.identity(6, 4), config, "input_diag", recipe, seed=0)
    assert isinstance(shared, SharedFit) and len(shared.history) == 6
    x_new, y_new = Xs[6], Ys[6]
    n = torch.tensor([0, 200])
    X = torch.stack([x_new[:200], x_new[:200]])
    Y = torch.stack([y_new[:200], y_new[:200]])
    stats = input_stats([x_new[:200], x_new[:200]])
    adapted = fit_adapters(shared, X, Y, n, Scaler.identity(2, 4), torch.tensor([1.0, 1.0]),
                           AdapterRecipe(steps=300, lr=3e-2), seed=0)
    assert stats.mean.shape == (2, 1, 4)
    with torch.no_grad():
        test = x_new[200:][None].expand(2, -1, -1)
        err = ((shared.out_scaler.inverse(adapted(test)) - y_new[200:]) ** 2).mean(dim=(1, 2))
    assert float(adapted.deviation().detach()[0]) == 0.0  # no rows, no change
    assert float(err[1]) < 0.5 * float(err[0]), err


def test_heteroscedastic_shared_model_learns_a_new_units_noise_and_folds():
    """Units whose targets are noisy where the first latent input is positive (noise sd
    0.3) and nearly clean elsewhere (0.02): the shared model's scale head, adapted to a new
    unit by beta-NLL and folded, predicts a larger sigma on the noisy half."""
    from anytip.models.heteroscedastic import split_heads

    Xs, Ys = fleet(7, 1500, seed=5)
    g = torch.Generator().manual_seed(1)
    for x, y in zip(Xs, Ys, strict=True):
        sd = torch.where(x[:, :1] > 0, 0.3, 0.02)
        y.add_(sd * torch.randn(y.shape, generator=g))
    data = FleetBatchData.from_units(
        [UnitTensors(x[:1200], y[:1200], x[1200:], y[1200:], f"u{i}") for i, (x, y) in
         enumerate(zip(Xs[:6], Ys[:6], strict=True))], output_names=("a", "b", "c"))
    config = MLPConfig(sizes=(4, 16, 16, 3), activation="tanh")
    recipe = TrainRecipe(name="t", lr=1e-2, batch_size=64, epochs=20, schedule="onecycle", warmup_frac=0.1)
    shared = train_shared(data, Scaler.identity(6, 4), config, "input_diag", recipe, seed=0, hetero_beta=0.5)
    assert shared.hetero_beta == 0.5 and shared.model.config.sizes[-1] == 6
    x_new, y_new = Xs[6], Ys[6]
    adapted = fit_adapters(shared, x_new[None, :600], y_new[None, :600], torch.tensor([600]),
                           Scaler.identity(1, 4), torch.tensor([1.0]), AdapterRecipe(steps=200, lr=3e-2))
    folded = adapted.fold()
    test = x_new[600:][None]
    with torch.no_grad():
        torch.testing.assert_close(folded(test), adapted(test), atol=1e-5, rtol=1e-5)
        _, log_var = split_heads(folded(test)[0])
    sigma = shared.out_scaler.std[0, 0] * (0.5 * log_var).exp()
    noisy = x_new[600:, 0] > 0
    ratio = sigma[noisy].median(0).values / sigma[~noisy].median(0).values
    assert bool((ratio > 2).all()), ratio
