"""Conformal quantiles, beta-NLL, fault injection and MAPIE agreement (no training)."""

import math

import numpy as np
import pytest
import torch

from anytip.data.faults import baseline_drift, dead_channel, saturation, stuck_channel
from anytip.models.heteroscedastic import beta_nll, gaussian_nll
from anytip.uncertainty import conformal as cp
from anytip.uncertainty.detect import auroc, flatline, window_means


def test_quantile_is_the_finite_sample_order_statistic():
    scores = np.arange(1, 20, dtype=float)[:, None]  # n = 19
    # ceil(20 * 0.9) = 18 -> the 18th smallest
    assert cp.conformal_quantile(scores, 0.1)[0] == 18.0
    assert cp.conformal_quantile(scores, 0.5)[0] == math.ceil(20 * 0.5)
    assert np.isinf(cp.conformal_quantile(scores[:5], 0.1)[0])  # too few rows for 0.9


@pytest.mark.parametrize("level", [0.5, 0.9, 0.95])
def test_split_conformal_covers_exchangeable_rows(level):
    rng = np.random.default_rng(0)
    n = 4000
    mu = rng.normal(size=(2 * n, 2))
    scale = np.exp(rng.normal(size=(2 * n, 2)) * 0.5)
    y = mu + scale * rng.standard_t(4, size=(2 * n, 2))
    for s in (None, scale):
        sc, st = (None, None) if s is None else (s[:n], s[n:])
        q = cp.conformal_quantile(cp.scores_of(mu[:n], y[:n], sc), 1 - level)
        lo, hi = cp.interval(mu[n:], q, st)
        assert np.all(np.abs(cp.coverage(lo, hi, y[n:]) - level) < 0.025)


def test_fleet_factor_corrects_a_biased_half_width():
    """Units whose own half-widths are all 2x too wide in one output and right in the other:
    the factor is 0.5 and 1, and own x factor then covers a fresh unit at the level. Exact
    geometric mean over units; bad shapes and non-positive or infinite widths refused."""
    rng = np.random.default_rng(3)
    sigma = np.exp(rng.normal(size=(6, 2)))
    observed = sigma * 1.645
    own = observed * np.array([2.0, 1.0])
    assert cp.fleet_factor(own, observed) == pytest.approx([0.5, 1.0])
    assert cp.fleet_factor(np.array([[1.0], [1.0]]), np.array([[2.0], [8.0]])) == pytest.approx([4.0])
    err = rng.normal(0, 0.7, (20_000, 2))
    half = cp.residual_halfwidth(rng.normal(0, 0.7, (20_000, 2)), 0.9) * np.array([2.0, 1.0])
    lo, hi = cp.interval(np.zeros_like(err), half * cp.fleet_factor(own, observed))
    assert np.all(np.abs(cp.coverage(lo, hi, err) - 0.9) < 0.01)
    for a, b in [(own[:, :1], observed), (own[0], observed[0]), (own[:0], observed[:0]),
                 (own * 0, observed), (own, observed * np.inf)]:
        with pytest.raises(ValueError, match="half-widths"):
            cp.fleet_factor(a, b)


def test_mapie_matches_own_split_conformal():
    rng = np.random.default_rng(1)
    mu_cal, mu = rng.normal(size=(301, 3)), rng.normal(size=(40, 3))
    y_cal = mu_cal + rng.normal(size=(301, 3))
    own = cp.conformal_quantile(cp.scores_of(mu_cal, y_cal), 0.1)
    np.testing.assert_allclose(cp.mapie_halfwidth(mu, y_cal, mu_cal, 0.9), own, rtol=1e-9)


def test_beta_nll_weights_by_detached_variance():
    mu = torch.zeros(6, requires_grad=True)
    log_var = torch.full((6,), math.log(4.0), requires_grad=True)
    y = torch.ones(6)
    beta_nll(mu, log_var, y, beta=1.0).sum().backward()
    # beta = 1: the mean's gradient is the MSE gradient (mu - y), whatever the variance
    np.testing.assert_allclose(mu.grad.numpy(), -np.ones(6), rtol=1e-6)
    mu2 = torch.zeros(6, requires_grad=True)
    lv2 = log_var.detach().clone().requires_grad_(True)
    beta_nll(mu2, lv2, y, beta=0.0).sum().backward()
    np.testing.assert_allclose(mu2.grad.numpy(), -np.ones(6) / 4.0, rtol=1e-6)
    assert torch.allclose(beta_nll(mu2, lv2, y, 0.0), gaussian_nll(mu2, lv2, y))


def test_faults_change_what_they_claim():
    x = np.random.default_rng(2).normal(1000, 300, size=(50, 8)).astype(np.float32)
    assert np.all(dead_channel(x, 3)[:, 3] == 0) and np.array_equal(dead_channel(x, 3)[:, 2], x[:, 2])
    assert np.all(stuck_channel(x, 1, 5.0)[:, 1] == 5.0)
    d = baseline_drift(x, 1000.0, np.array([0]))
    np.testing.assert_allclose(d[:, 0] - x[:, 0], 1000.0, rtol=1e-5)
    assert np.array_equal(d[:, 1:], x[:, 1:])
    assert saturation(x, 900.0).max() <= 900.0


def test_flatline_flags_a_stuck_channel_window():
    x = np.random.default_rng(3).normal(0, 8, size=(4000, 8))  # barometer noise only
    stuck = stuck_channel(x, 5, 12.0)
    assert auroc(flatline(x, 100), flatline(stuck, 100)) == 1.0
    assert window_means(np.arange(10.0), 5).tolist() == [2.0, 7.0]


def test_patch_bootstrap_spread_matches_patch_to_patch_scatter():
    from anytip.uncertainty.coverage_bootstrap import (
        bootstrap_test_patches,
        conformal_patch_bootstrap,
        exact_method_band,
    )

    rng = np.random.default_rng(4)
    n_patch, rows = 40, 100
    p = np.clip(rng.normal(0.9, 0.06, n_patch), 0, 1)  # each patch's own coverage
    patch = np.repeat(np.arange(n_patch), rows)
    covered = (rng.random(n_patch * rows) < np.repeat(p, rows))[:, None]
    boot = bootstrap_test_patches(covered, patch, 2000, rng)
    expected = np.std([covered[patch == i].mean() for i in range(n_patch)]) / np.sqrt(n_patch)
    assert abs(boot.std() / expected - 1) < 0.15
    band = exact_method_band(boot, covered.mean(0), 0.9, (0.87, 0.93))
    assert band["lo"][0] < 0.9 < band["hi"][0] and 0 <= band["p_outside"][0] <= 1
    # drawing the calibration patches again as well can only widen the spread
    resid = np.abs(rng.normal(size=(n_patch * rows, 1)))
    both = conformal_patch_bootstrap(np.abs(rng.normal(size=(3000, 1))), np.repeat(np.arange(30), 100), None,
                                     resid, patch, 0.9, 400, rng)
    assert both.std() > bootstrap_test_patches(resid <= 1.645, patch, 400, rng).std()
