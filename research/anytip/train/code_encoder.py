"""A new unit's response-transfer codes predicted from order-free statistics of its pressures in
ordinary use, learnt across the units of a response model (research log entries 30, 35 and 44).

The statistics (`stream_features`) say little alone: the ridge regression from them (`CodeEncoder`)
explains about 40% of the code variance (leave-one-unit-out, with the many units of a response
model's extra units; on 16 registry units alone it explains none). Its codes are a start, not an
answer: the label-free search and fit started from them (`train.label_free.label_free_codes`) end in
a better basin of their objective than from codes zero (entry 44).

Shapes: n rows, C barometers, f features (C * 6 + C * (C - 1) / 2), k code_dim.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch
from torch import Tensor

ENCODER_QUANTILES = (0.5, 0.75, 0.9, 0.97, 0.995)
PA_FLOOR = 100.0  # Pa: a quantile below it is sensor noise, floored before its log
ALPHAS = tuple(10.0 ** np.arange(-3, 5.5, 0.5))  # ridge penalties tried, times the unit count


def stream_features(P: np.ndarray) -> np.ndarray:
    """Label-free statistics of a unit's unlabeled pressures P (n, C) Pa, independent of row order:
    each barometer's log quantiles (ENCODER_QUANTILES, floored at PA_FLOOR) and log standard
    deviation, and the barometers' correlations; (f,)."""
    q = np.log(np.maximum(np.quantile(P, ENCODER_QUANTILES, axis=0), PA_FLOOR))
    sd = np.log(np.maximum(P.std(0), PA_FLOOR))
    corr = np.nan_to_num(np.corrcoef(P.T))[np.triu_indices(P.shape[1], 1)]
    return np.concatenate([q.ravel(), sd, corr])


@dataclass(frozen=True)
class CodeEncoder:
    """Ridge regression from a unit's stream features (f,) to its codes (C, k), learnt across units;
    the penalty chosen by leave-one-unit-out error of the codes whitened by the codes' prior spread.
    loo_r2: the share of that whitened code variance the left-out predictions explain (0: no better
    than the units' mean code)."""

    f_mean: np.ndarray
    f_std: np.ndarray
    z_mean: np.ndarray
    weights: np.ndarray
    scale: np.ndarray
    alpha: float
    loo_r2: float

    @classmethod
    def fit(cls, F: np.ndarray, Z: np.ndarray, code_var: np.ndarray) -> CodeEncoder:
        """F (n, f) features, Z (n, C, k) codes, code_var (k,); at least two units."""
        n = len(F)
        if n < 2:
            raise ValueError(f"a code encoder learns across units: got {n}")
        f_mean, f_std = F.mean(0), np.maximum(F.std(0), 1e-9)
        scale = np.sqrt(code_var)
        Y = (Z / scale).reshape(n, -1)
        z_mean = Y.mean(0)
        U, S, Vt = np.linalg.svd((F - f_mean) / f_std, full_matrices=False)
        Yc = Y - z_mean
        best = (np.inf, 0.0)
        for a in ALPHAS:
            d = S**2 / (S**2 + a * n)
            h = (U**2 * d).sum(1) + 1 / n
            loo = (Yc - U @ (d[:, None] * (U.T @ Yc))) / (1 - h)[:, None]
            best = min(best, (float((loo**2).mean()), a * n))
        err, alpha = best
        weights = Vt.T @ ((S / (S**2 + alpha))[:, None] * (U.T @ Yc))
        total = float((Yc**2).mean())
        return cls(f_mean, f_std, z_mean, weights, scale, alpha, 1 - err / total if total > 0 else 0.0)

    def __call__(self, features: np.ndarray) -> Tensor:
        """The codes (C, k) float32 of a unit's features (f,)."""
        y = self.z_mean + ((features - self.f_mean) / self.f_std) @ self.weights
        return torch.from_numpy((y.reshape(-1, len(self.scale)) * self.scale).astype(np.float32))
