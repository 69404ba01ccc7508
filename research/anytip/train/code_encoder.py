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
from typing import Any

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
    with np.errstate(invalid="ignore", divide="ignore"):  # a constant barometer correlates with none: 0
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

    def to_json(self) -> dict[str, Any]:
        """The encoder as JSON values (what a response model's metadata records, `from_json`)."""
        return {"f_mean": self.f_mean.tolist(), "f_std": self.f_std.tolist(), "z_mean": self.z_mean.tolist(),
                "weights": self.weights.tolist(), "scale": self.scale.tolist(), "alpha": float(self.alpha),
                "loo_r2": float(self.loo_r2)}

    @classmethod
    def from_json(cls, values: Any) -> CodeEncoder:
        """`to_json`'s values read back; ValueError naming the key where one is missing, not finite, of
        the wrong shape, or where a spread is not positive."""
        if not isinstance(values, dict):
            raise ValueError(f"expected a mapping, got {type(values).__name__}")
        got = {key: _finite_array(values, key) for key in ("f_mean", "f_std", "z_mean", "weights", "scale",
                                                             "alpha", "loo_r2")}
        f, m, k = len(got["f_mean"]), len(got["z_mean"]), len(got["scale"])
        wanted = {"f_mean": (f,), "f_std": (f,), "z_mean": (m,), "weights": (f, m), "scale": (k,),
                  "alpha": (), "loo_r2": ()}
        for key, shape in wanted.items():
            if got[key].shape != shape:
                raise ValueError(f"{key}: shape {got[key].shape}, expected {shape}")
        if not k or m % k or not (got["f_std"] > 0).all() or not (got["scale"] > 0).all():
            raise ValueError("f_std and scale must be positive, and z_mean a whole number of codes of "
                             f"len(scale) = {k}")
        return cls(got["f_mean"], got["f_std"], got["z_mean"], got["weights"], got["scale"],
                   float(got["alpha"]), float(got["loo_r2"]))

    def __call__(self, features: np.ndarray) -> Tensor:
        """The codes (C, k) float32 of a unit's features (f,); ValueError for features of another
        length (a unit with another barometer count)."""
        if features.shape != self.f_mean.shape:
            raise ValueError(f"the encoder reads {len(self.f_mean)} features, got {features.shape}")
        y = self.z_mean + ((features - self.f_mean) / self.f_std) @ self.weights
        return torch.from_numpy((y.reshape(-1, len(self.scale)) * self.scale).astype(np.float32))


def _finite_array(values: dict[str, Any], key: str) -> np.ndarray:
    """values[key] as a float64 array; ValueError naming the key where it is missing or not finite."""
    try:
        out = np.asarray(values[key], dtype=np.float64)
    except (KeyError, TypeError, ValueError) as e:
        raise ValueError(f"{key}: missing or not numbers ({e})") from None
    if not np.isfinite(out).all():
        raise ValueError(f"{key}: not finite")
    return out
