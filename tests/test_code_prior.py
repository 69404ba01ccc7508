"""A new unit's code prior (train/code_prior.py): the first recipe's diagonal prior, each
barometer's own mean and covariance, and the registry's units' centre and spread."""

import numpy as np
import pytest
import torch

from anytip.train.code_prior import CodePrior, barometer_prior, code_prior, diagonal_prior, registry_prior

C, K = 3, 4


def correlated(n: int, mean: np.ndarray, cov: np.ndarray, seed: int) -> torch.Tensor:
    """(n, C, K) codes, every barometer c drawn from N(mean[c], cov[c])."""
    rng = np.random.default_rng(seed)
    draws = [rng.multivariate_normal(mean[c], cov[c], size=n) for c in range(C)]
    return torch.tensor(np.stack(draws, 1), dtype=torch.float32)


def covariances(seed: int) -> np.ndarray:
    """(C, K, K) covariances with strong correlations and spreads from 0.1 to 1."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(C):
        A = rng.normal(size=(K, K))
        out.append(A @ A.T / K + 0.05 * np.eye(K))
    return np.stack(out)


def test_the_diagonal_prior_is_the_first_recipes_penalty_and_pull_is_its_gradient():
    g = torch.Generator().manual_seed(0)
    code_var = torch.rand(K, generator=g) + 0.1
    codes = torch.randn(5, C, K, generator=g)
    diagonal = diagonal_prior(code_var, C)
    torch.testing.assert_close(diagonal.penalty(codes), (codes**2 / code_var).sum(-1) / 2)
    full = barometer_prior(correlated(200, np.ones((C, K)), covariances(1), seed=2))
    z = codes.clone().requires_grad_(True)
    full.penalty(z).sum().backward()
    torch.testing.assert_close(full.pull(codes), -z.grad, rtol=1e-4, atol=1e-5)
    assert (full.penalty(full.mean) == 0).all()


def test_the_barometer_prior_holds_each_barometers_own_mean_and_covariance():
    mean = np.arange(C * K, dtype=float).reshape(C, K) / 10
    cov = covariances(3)
    prior = barometer_prior(correlated(20_000, mean, cov, seed=4))
    np.testing.assert_allclose(prior.mean.numpy(), mean, atol=0.05)
    for c in range(C):
        learnt = np.linalg.inv(prior.precision[c].double().numpy())
        assert np.linalg.norm(learnt - cov[c]) < 0.05 * np.linalg.norm(cov[c])


def test_the_registry_prior_is_centred_and_scaled_on_the_registrys_units():
    """Simulated units about zero, the registry's units about another centre with twice the spread:
    the prior keeps the covariance's shape and takes the registry's centre and variance."""
    cov = covariances(5)
    many = correlated(4000, np.zeros((C, K)), cov, seed=6)
    centre = np.full((C, K), 0.7)
    registry = correlated(400, centre, 4 * cov, seed=7)
    codes = torch.cat([many, registry])
    prior = registry_prior(codes, range(4000, 4400))
    np.testing.assert_allclose(prior.mean.numpy(), centre, atol=0.2)
    shape = barometer_prior(codes)
    scale = (shape.precision / prior.precision).mean((1, 2))  # the variance multiplier per barometer
    assert ((scale > 2.5) & (scale < 5.5)).all(), scale
    on_itself = registry_prior(many, range(4000))
    ratio = (barometer_prior(many).precision / on_itself.precision).mean((1, 2))
    assert ((ratio > 0.9) & (ratio < 1.1)).all(), ratio  # the registry is the fleet: nothing moves


def test_a_prior_kind_is_named_and_too_few_units_fall_back_to_what_they_can_learn():
    codes = correlated(10, np.zeros((C, K)), covariances(8), seed=9)
    code_var = codes.var(0).mean(0)
    with pytest.raises(ValueError, match="code_prior 'wide'"):
        code_prior("wide", codes, code_var)
    with pytest.raises(ValueError, match="at least two of the registry's units, got 1"):
        registry_prior(codes, [3, 3])
    lone = code_prior("registry", codes, code_var, [3])  # one registry unit: nothing to centre on
    torch.testing.assert_close(lone.precision, barometer_prior(codes).precision)
    alone = code_prior("registry", codes[:1], code_var)  # one unit: no spread to learn
    torch.testing.assert_close(alone.precision, diagonal_prior(code_var, C).precision)
    assert isinstance(alone, CodePrior)
