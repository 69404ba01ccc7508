"""Adapter priors: the empirical-Bayes Gaussian is the Mahalanobis distance it claims to be, new
units start at the training units' mean, and every adapter family folds within the float32
rounding bound of the folded network."""

from __future__ import annotations

import numpy as np
import pytest
import torch

from anytip.deploy.rounding import U_FLOAT32, export_tolerance
from anytip.errors import AnytipError
from anytip.models.adapted import AdaptedMLP
from anytip.models.mlp import MLPConfig
from anytip.models.scaler import Scaler
from anytip.train.adapt import AdapterRecipe, SharedFit, fit_adapters
from anytip.train.adapter_prior import AdapterPrior, flat_adapters, make_prior
from anytip.train.recipe import FAST
from test_adapted import KINDS, randomise


def trained_units(n_units: int = 12, kind: str = "input_affine+film", seed: int = 0) -> AdaptedMLP:
    """A shared model whose training units' adapters spread differently per parameter group."""
    model = AdaptedMLP(n_units, MLPConfig(), kind, seed=seed)
    g = torch.Generator().manual_seed(seed)
    with torch.no_grad():
        for k, p in enumerate(model.adapter.values()):
            p.add_((0.02 * 2**k) * torch.randn(p.shape, generator=g))
    return model


def test_the_penalty_is_the_scaled_mahalanobis_distance_of_the_covariance():
    model = trained_units()
    prior = AdapterPrior.empirical(model, rank=3)
    cov = torch.diag(prior.diag.double()) + prior.basis.double() @ prior.basis.double().T
    new = randomise(AdaptedMLP(5, MLPConfig(), model.kind, seed=1), seed=2)
    d = flat_adapters(new).double() - prior.mean.double()
    direct = (d @ torch.linalg.inv(cov) * d).sum(1) * torch.trace(cov) / cov.shape[0]
    torch.testing.assert_close(prior.penalty(new).double(), direct, rtol=1e-4, atol=1e-6)


def test_new_units_start_at_the_training_units_mean_where_the_penalty_is_zero():
    model = trained_units()
    prior = make_prior("empirical", model, rank=4)
    new = AdaptedMLP(3, MLPConfig(), model.kind)
    prior.start(new)
    torch.testing.assert_close(flat_adapters(new), flat_adapters(model).mean(0).expand(3, -1))
    assert float(prior.penalty(new).detach().abs().max()) < 1e-6
    assert make_prior("identity", model) is None
    with pytest.raises(AnytipError, match="at least 3"):
        AdapterPrior.empirical(trained_units(n_units=2))
    with pytest.raises(AnytipError, match="unknown adapter prior"):
        make_prior("flat", model)


def test_the_empirical_prior_pulls_along_the_directions_the_fleet_varies_in():
    model = trained_units()
    prior = AdapterPrior.empirical(model, rank=4)
    typical = AdaptedMLP(1, MLPConfig(), model.kind)
    prior.start(typical)
    wide, narrow = typical, AdaptedMLP(1, MLPConfig(), model.kind)
    prior.start(narrow)
    keys = list(model.adapter)
    with torch.no_grad():  # the same step along the widest and the narrowest parameter group
        wide.adapter[keys[-1]].add_(0.05)
        narrow.adapter[keys[0]].add_(0.05 * (model.adapter[keys[-1]][0].numel()
                                            / model.adapter[keys[0]][0].numel()) ** 0.5)
    assert float(prior.penalty(wide).detach()) < float(prior.penalty(narrow).detach()) / 10


def test_fitting_with_the_empirical_prior_beats_the_mean_adapter_on_a_unit_from_the_prior():
    torch.manual_seed(0)
    model = trained_units(16)
    unit_scaler = Scaler(torch.zeros(1, 1, 8), torch.ones(1, 1, 8))
    shared = SharedFit(model, Scaler(torch.zeros(16, 1, 8), torch.ones(16, 1, 8)),
                       Scaler(torch.zeros(1, 1, 5), torch.ones(1, 1, 5)), [f"U{k}" for k in range(16)],
                       FAST, 0)
    prior = AdapterPrior.empirical(model, rank=4)
    truth = AdaptedMLP(1, MLPConfig(), model.kind, seed=0)
    unit3 = {f"adapter.{k}": v[3:4] for k, v in model.adapter.items()}
    weights = {k: v for k, v in model.state_dict().items() if not k.startswith("adapter.")}
    truth.load_state_dict({**weights, **unit3})
    X = torch.randn(1, 1000, 8)
    with torch.no_grad():
        Y = truth(X)
    fitted = fit_adapters(shared, X, Y, torch.tensor([1000]), unit_scaler, torch.tensor([1.0]),
                          AdapterRecipe(steps=600), adapter_prior=prior)
    start = AdaptedMLP(1, MLPConfig(), model.kind)
    start.load_state_dict({**weights, **{f"adapter.{k}": v for k, v in start.adapter.items()}})
    prior.start(start)
    Xt = torch.randn(1, 500, 8)
    with torch.no_grad():
        err_fit = float(((fitted(Xt) - truth(Xt)) ** 2).mean())
        err_mean = float(((start(Xt) - truth(Xt)) ** 2).mean())
    assert err_fit < 0.5 * err_mean


def layers_of(folded, unit: int) -> list:
    last = len(folded.weights) - 1
    return [(W[unit].detach().double().numpy(), b[unit, 0].detach().double().numpy(),
             "relu" if k < last else None)
            for k, (W, b) in enumerate(zip(folded.weights, folded.biases, strict=True))]


@pytest.mark.parametrize("kind", KINDS)
def test_every_adapter_family_folds_within_the_float32_rounding_bound(kind):
    model = randomise(AdaptedMLP(3, MLPConfig(), kind, seed=5), seed=6).double()
    x = torch.randn(3, 400, 8, dtype=torch.float64) * 2
    with torch.no_grad():
        exact = model(x).numpy()  # the adapted model in float64: the reference
        folded = model.fold()  # folded in float64, deployed in float32
        assert folded.weights[0].dtype == torch.float64
        deployed = folded.float()(x.float()).double().numpy()
    for u in range(3):
        tol = export_tolerance(layers_of(folded, u), x[u].numpy(), u=U_FLOAT32)
        assert np.all(np.abs(deployed[u] - exact[u]) <= tol), kind
        assert np.abs(deployed[u] - exact[u]).max() > 0  # float32 really differs: the bound is tested
