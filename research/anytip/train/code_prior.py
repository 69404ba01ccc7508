"""The Gaussian prior over a new unit's response-transfer codes (train/response.py `fit_codes`,
train/label_free.py `joint_fit`; research log entry 86).

A unit's codes are C barometer codes of k numbers each. The prior is one Gaussian per barometer,
mean (C, k) and precision (C, k, k), so a barometer's code still depends on its own pressures and
the prior alone: the code fit stays C problems of k numbers. Three kinds (`CODE_PRIORS`):

- `diagonal`: mean zero, the training codes' variance per code dimension pooled over barometers
  (`ResponseFit.code_var`), no correlation. The first recipe; every saved model's default.
- `barometer`: each barometer's own mean and full covariance over every unit the response model
  learnt (extra simulated units included), Ledoit-Wolf shrunk towards its diagonal.
- `registry`: the `barometer` covariance's shape, centred on the registry's own training units'
  mean and scaled, per barometer, to their spread about it. Where a response model learnt many
  simulated units of another physical model, the registry's units can lie further out than those
  units (other16's: about twice the variance the simulated units give, entry 86).

Shapes: U units, C barometers, k code_dim.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import torch
from sklearn.covariance import ledoit_wolf
from torch import Tensor

CODE_PRIORS = ("diagonal", "barometer", "registry")
MIN_SPREAD = 1e-8  # a code dimension's variance floor (as ResponseFit.code_var's)


@dataclass(frozen=True)
class CodePrior:
    """mean (C, k) and precision (C, k, k): barometer c's code z_c has the prior
    exp(-(z_c - mean_c)^T precision_c (z_c - mean_c) / 2)."""

    mean: Tensor
    precision: Tensor

    def penalty(self, codes: Tensor) -> Tensor:
        """(..., C): the negative log prior of codes (..., C, k), up to a constant, per barometer."""
        d = codes - self.mean
        return (d * self.apply(d)).sum(-1) / 2

    def apply(self, d: Tensor) -> Tensor:
        """precision_c d_c for every barometer of d (..., C, k): (..., C, k)."""
        return torch.einsum("ckj,...cj->...ck", self.precision, d)

    def pull(self, codes: Tensor) -> Tensor:
        """(..., C, k): minus the penalty's gradient at codes (..., C, k)."""
        return -self.apply(codes - self.mean)

    def to(self, device: torch.device | str) -> CodePrior:
        return CodePrior(self.mean.to(device), self.precision.to(device))


def diagonal_prior(code_var: Tensor, n_channels: int) -> CodePrior:
    """Mean zero, precision diag(1 / code_var) for each of `n_channels` barometers; code_var (k,)."""
    k = code_var.shape[0]
    precision = torch.diag_embed(1 / code_var).expand(n_channels, k, k).clone()
    return CodePrior(code_var.new_zeros(n_channels, k), precision)


def barometer_prior(codes: Tensor) -> CodePrior:
    """Each barometer's mean and Ledoit-Wolf covariance (standardised per dimension, so shrunk
    towards the diagonal) over the units' codes (U, C, k), U >= 2."""
    means, precisions = zip(*_barometer_moments(_as_array(codes)), strict=True)
    return _prior(list(means), list(precisions), codes)


def registry_prior(codes: Tensor, registry: Sequence[int]) -> CodePrior:
    """The `barometer` prior of codes (U, C, k) with, per barometer, the mean of the registry's units
    (`registry`: indices into U, at least two) and the covariance scaled by s_c, their mean squared
    Mahalanobis distance about that mean over k (unbiased: times n / (n - 1))."""
    if len(set(registry)) < 2:
        raise ValueError(f"a registry prior needs at least two of the registry's units, "
                         f"got {len(set(registry))}")
    Z = _as_array(codes)
    R = Z[sorted(set(registry))]
    n, k = R.shape[0], Z.shape[2]
    means, precisions = [], []
    for c, (_, precision) in enumerate(_barometer_moments(Z)):
        mean = R[:, c].mean(0)
        d = R[:, c] - mean
        scale = np.einsum("ui,ij,uj->", d, precision, d) / (n - 1) / k
        means.append(mean)
        precisions.append(precision / max(scale, MIN_SPREAD))
    return _prior(means, precisions, codes)


def code_prior(kind: str, codes: Tensor, code_var: Tensor, registry: Sequence[int] = ()) -> CodePrior:
    """The prior `kind` (`CODE_PRIORS`) from the units' codes (U, C, k), their pooled variance
    code_var (k,) and the registry's own units among them (indices into U, for `registry`). With a
    single unit every kind falls back to `diagonal` (there is no spread to learn), and `registry`
    with fewer than two of the registry's units to `barometer` (nothing to centre it on)."""
    if kind not in CODE_PRIORS:
        raise ValueError(f"code_prior {kind!r}: expected one of {', '.join(CODE_PRIORS)}")
    if kind == "diagonal" or codes.shape[0] < 2:
        return diagonal_prior(code_var, codes.shape[1])
    if kind == "barometer" or len(set(registry)) < 2:
        return barometer_prior(codes)
    return registry_prior(codes, registry)


def _as_array(codes: Tensor) -> np.ndarray:
    if codes.ndim != 3 or codes.shape[0] < 2:
        raise ValueError(f"codes of shape {tuple(codes.shape)}: expected (units >= 2, C, k)")
    return codes.detach().double().cpu().numpy()


def _barometer_moments(Z: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Per barometer of codes Z (U, C, k): its mean (k,) and the precision (k, k) of its shrunk
    covariance (`_shrunk_covariance`), in float64."""
    moments = []
    for c in range(Z.shape[1]):
        mean, cov = _shrunk_covariance(Z[:, c])
        moments.append((mean, np.linalg.inv(cov)))
    return moments


def _shrunk_covariance(Z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mean (k,) and Ledoit-Wolf covariance (k, k) of one barometer's codes Z (U, k)."""
    mean = Z.mean(0)
    sd = np.maximum(Z.std(0), MIN_SPREAD**0.5)
    shrunk, _ = ledoit_wolf((Z - mean) / sd)
    cov = shrunk * np.outer(sd, sd)
    return mean, cov + MIN_SPREAD * np.eye(len(mean))


def _prior(means: list[np.ndarray], precisions: list[np.ndarray], like: Tensor) -> CodePrior:
    """The prior of per-barometer means (k,) and precisions (k, k), in like's dtype and device."""
    mean = torch.as_tensor(np.stack(means), dtype=like.dtype, device=like.device)
    return CodePrior(mean, torch.as_tensor(np.stack(precisions), dtype=like.dtype, device=like.device))
