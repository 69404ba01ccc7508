"""Priors over a new unit's adapter: where its fit starts and what pulls it back.

A new unit's adapter is fitted on a few presses; the prior keeps it plausible. Two families:

- `identity`: start at the identity adapter, penalty |theta - identity|^2 (isotropic);
- `empirical`: an empirical-Bayes Gaussian learnt from the training units' adapters: start at
  their mean mu, penalty the Mahalanobis distance (theta - mu)^T S^-1 (theta - mu) under a
  covariance S = diag(d) + B B^T of rank `rank` plus a diagonal (the training units' adapters
  spread very differently per parameter group, which an isotropic prior ignores). It is
  multiplied by trace(S) / P, so a typical direction costs what it costs under the identity
  prior and one grid of prior strengths serves both families.

theta is one unit's adapter tensors flattened in the model's key order, P numbers.
"""

from __future__ import annotations

from typing import Literal

import torch
from torch import Tensor

from anytip.errors import AnytipError
from anytip.models.adapted import AdaptedMLP

PriorFamily = Literal["identity", "empirical"]


def flat_adapters(model: AdaptedMLP) -> Tensor:
    """(U, P) every unit's adapter tensors, flattened in key order."""
    return torch.cat([p.flatten(1) for p in model.adapter.values()], dim=1)


class AdapterPrior:
    """mean (P,), diag (P,) and basis (P, k): the covariance diag(diag) + basis basis^T."""

    def __init__(self, family: PriorFamily, mean: Tensor, diag: Tensor, basis: Tensor):
        self.family, self.mean, self.diag, self.basis = family, mean, diag, basis
        inv = 1.0 / diag
        self._w = basis * inv[:, None]  # D^-1 B (P, k)
        self._core = torch.linalg.inv(torch.eye(basis.shape[1], dtype=basis.dtype, device=basis.device)
                                      + basis.T @ self._w)  # (I + B^T D^-1 B)^-1, Woodbury
        self._inv = inv
        self._scale = float((diag.sum() + (basis**2).sum()) / diag.numel())

    @classmethod
    def empirical(cls, model: AdaptedMLP, rank: int = 4, floor: float = 1e-6) -> AdapterPrior:
        """From the U training units' adapters of a trained shared model: their mean, the top
        `rank` principal directions of their spread, and the remaining per-parameter variance
        (floored at `floor` times its mean, so no direction is free)."""
        theta = flat_adapters(model).detach().double()
        U = theta.shape[0]
        if U < 3:
            raise AnytipError(f"an empirical adapter prior needs the adapters of at least 3 training "
                              f"units, got {U}")
        mean = theta.mean(0)
        resid = (theta - mean) / (U - 1) ** 0.5
        _, s, vt = torch.linalg.svd(resid, full_matrices=False)
        k = max(0, min(rank, U - 2))
        basis = vt[:k].T * s[:k]
        rest = resid - (resid @ vt[:k].T) @ vt[:k]
        var = (rest**2).sum(0)
        diag = var.clamp_min(floor * float(var.mean()) + 1e-12)
        return cls("empirical", mean.float(), diag.float(), basis.float())

    def to(self, device: torch.device | str) -> AdapterPrior:
        return AdapterPrior(self.family, self.mean.to(device), self.diag.to(device), self.basis.to(device))

    def penalty(self, model: AdaptedMLP) -> Tensor:
        """(M,) each unit's scaled squared distance from the prior mean."""
        d = flat_adapters(model) - self.mean
        quad = (d**2 * self._inv).sum(1)
        if self.basis.shape[1]:
            z = d @ self._w
            quad = quad - ((z @ self._core) * z).sum(1)
        return quad * self._scale

    @torch.no_grad()
    def start(self, model: AdaptedMLP) -> None:
        """Set every unit's adapter to the prior mean."""
        offset = 0
        for p in model.adapter.values():
            n = p[0].numel()
            p.copy_(self.mean[offset:offset + n].reshape(p.shape[1:]).expand_as(p))
            offset += n


def make_prior(family: PriorFamily, model: AdaptedMLP, rank: int = 4) -> AdapterPrior | None:
    """The prior of `family` for new units of a trained shared model; None for `identity`, which
    the adapted model itself implements (`AdaptedMLP.deviation`, adapters reset to the identity)."""
    if family == "identity":
        return None
    if family == "empirical":
        return AdapterPrior.empirical(model, rank)
    raise AnytipError(f"unknown adapter prior {family!r}; use identity or empirical")
