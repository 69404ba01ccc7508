"""Heteroscedastic output heads: an MLP with 2d outputs, d means and d log-variances.

The network is still a plain MLP (8 -> 12 -> 64 -> 64 -> 10 for the paper's shape), so it
folds, saves and exports like any other; only the meaning of the last d outputs differs.
Both halves live in standardised output units: output k is mu_k in units of the unit's
output std s_k, output d + k is log(sigma_k^2 / s_k^2). In physical units
mu = mean_k + s_k * z_k and sigma = s_k * exp(0.5 * log_var_k).
"""

from __future__ import annotations

import math

import torch
from torch import Tensor

from anytip.models.mlp import MLPConfig
from anytip.models.scaler import Scaler

LOG_VAR_MIN, LOG_VAR_MAX = -12.0, 6.0  # clamp on standardised log-variances


def hetero_config(base: MLPConfig) -> MLPConfig:
    """The same MLP with twice the outputs: d means, then d log-variances."""
    return MLPConfig(sizes=(*base.sizes[:-1], 2 * base.sizes[-1]), activation=base.activation)


def split_heads(z: Tensor) -> tuple[Tensor, Tensor]:
    """(..., 2d) raw outputs -> mean (..., d) and clamped log-variance (..., d), standardised."""
    d = z.shape[-1] // 2
    return z[..., :d], z[..., d:].clamp(LOG_VAR_MIN, LOG_VAR_MAX)


def gaussian_nll(mu: Tensor, log_var: Tensor, y: Tensor) -> Tensor:
    """Per-element Gaussian negative log-likelihood, constant included: same shape as y."""
    return 0.5 * (log_var + (y - mu) ** 2 / log_var.exp() + math.log(2 * math.pi))


def beta_nll(mu: Tensor, log_var: Tensor, y: Tensor, beta: float = 0.5) -> Tensor:
    """beta-NLL (Seitzer et al., ICLR 2022): the NLL of each element weighted by
    stop_gradient(sigma^2) ** beta. beta = 0 is the plain NLL, beta = 1 gives the mean the
    gradient of MSE. Same shape as y."""
    weight = log_var.detach().mul(beta).exp()
    return weight * gaussian_nll(mu, log_var, y)


def unit_loss(out: Tensor, Y: Tensor, hetero_beta: float | None) -> Tensor:
    """Each model's loss (M,) on standardised outputs out (M, B, d or 2d) and targets
    Y (M, B, d): MSE, or beta-NLL for heteroscedastic heads."""
    if hetero_beta is None:
        return ((out - Y) ** 2).mean(dim=(1, 2))
    mu, log_var = split_heads(out)
    return beta_nll(mu, log_var, Y, hetero_beta).mean(dim=(1, 2))


def output_scaler_2d(out_scaler: Scaler) -> Scaler:
    """The (U, 1, 2d) scaler a heteroscedastic model is saved with: the means use the
    original scaler; a log-variance output z is shifted by 2 log std, so the saved model
    gives log sigma^2 in physical units (N^2, rad^2). The shift is affine: it folds into the
    last layer and an exported model needs no exp() on the device."""
    ones = torch.ones_like(out_scaler.std)
    return Scaler(torch.cat([out_scaler.mean, 2 * out_scaler.std.log()], -1),
                  torch.cat([out_scaler.std, ones], -1))


def to_physical(mu_z: Tensor, log_var_z: Tensor, out_scaler: Scaler) -> tuple[Tensor, Tensor]:
    """Standardised mean and log-variance (U, N, d) -> physical mean and sigma (U, N, d)."""
    return out_scaler.inverse(mu_z), out_scaler.std * (0.5 * log_var_z).exp()
