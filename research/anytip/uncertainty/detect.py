"""Signals that a unit's estimate should not be trusted, and how well they separate
clean rows from faulty ones (AUROC).

Every signal maps rows to one number per row, larger = less trustworthy:
- `scale`: the heteroscedastic member's predicted sigma, mean over outputs of
  log(sigma_k / s_k) (s_k the unit's output std);
- `disagreement`: the ensemble's std of member means, mean over outputs of log(spread / s_k);
- `novelty`: Mahalanobis distance of the input from the unit's training inputs (an 8x8
  inverse covariance and a mean per unit, cheap on the microcontroller);
- `knn_novelty`: distance to the k-th nearest training input (offline reference).

A persistent fault (dead or stuck channel, drift) is also judged on windows: the mean of
a signal over `window` consecutive rows.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from sklearn.metrics import roc_auc_score


@dataclass
class InputNovelty:
    """Mahalanobis novelty of one unit's inputs: mean (C,) Pa, inverse covariance (C, C)."""

    mean: np.ndarray
    precision: np.ndarray

    @classmethod
    def fit(cls, x: np.ndarray, ridge: float = 1e-6) -> InputNovelty:
        """Fit on training rows x (n, C) Pa; a ridge relative to the mean variance keeps a
        constant channel from making the covariance singular."""
        x = x.astype(np.float64)
        cov = np.cov(x, rowvar=False)
        cov += ridge * np.trace(cov) / len(cov) * np.eye(len(cov))
        return cls(x.mean(0), np.linalg.inv(cov))

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """(n, C) Pa -> (n,) Mahalanobis distance."""
        return mahalanobis(x.astype(np.float64) - self.mean, self.precision)


def mahalanobis(d: np.ndarray, precision: np.ndarray) -> np.ndarray:
    """(n,) distances sqrt(d_n^T P d_n) of offsets d (n, C) from a mean, P the precision (C, C)."""
    return np.sqrt(np.einsum("ni,ij,nj->n", d, precision, d))


def scale_signal(sigma: np.ndarray, out_std: np.ndarray) -> np.ndarray:
    """Predicted sigma (n, d) physical, output std (d,) -> (n,) mean log relative sigma."""
    return np.log(sigma / out_std).mean(1)


def disagreement_signal(spread: np.ndarray, out_std: np.ndarray) -> np.ndarray:
    """Std of members' means (n, d) physical -> (n,) mean log relative spread."""
    return np.log(spread / out_std + 1e-12).mean(1)


def auroc(clean: np.ndarray, faulty: np.ndarray) -> float:
    """Area under the ROC curve of a signal that should be larger on `faulty` rows."""
    y = np.concatenate([np.zeros(len(clean)), np.ones(len(faulty))])
    return float(roc_auc_score(y, np.concatenate([clean, faulty])))


def unit_signals(mu: np.ndarray, sigma: np.ndarray, out_std: np.ndarray,
                 novelty: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """All signals of one unit's rows from its members' means and sigmas (K, n, d), its
    output std (d,) and the rows' input-novelty signals (n,) by name."""
    spread = mu.std(0)
    return {"scale": scale_signal(sigma[0], out_std),
            "ensemble_scale": scale_signal(np.sqrt((sigma ** 2).mean(0) + spread ** 2), out_std),
            "disagreement": disagreement_signal(spread, out_std), **novelty}


@dataclass
class KnnNovelty:
    """Distance to the k-th nearest training input (standardised per channel): an offline
    reference for novelty, too large for the microcontroller. ref (m, C), std (C,) Pa."""

    ref: np.ndarray
    std: np.ndarray
    k: int = 5

    @classmethod
    def fit(cls, x: np.ndarray, max_ref: int = 5000, k: int = 5, seed: int = 0) -> KnnNovelty:
        rng = np.random.default_rng(seed)
        ref = x if len(x) <= max_ref else x[rng.choice(len(x), max_ref, replace=False)]
        std = x.std(0) + 1e-6
        return cls(ref / std, std, k)

    def __call__(self, x: np.ndarray, chunk: int = 4096) -> np.ndarray:
        import torch

        ref = torch.as_tensor(self.ref, dtype=torch.float32)
        out = []
        for i in range(0, len(x), chunk):
            q = torch.as_tensor(x[i:i + chunk] / self.std, dtype=torch.float32)
            out.append(torch.cdist(q, ref).topk(self.k, largest=False).values[:, -1].numpy())
        return np.concatenate(out) if out else np.zeros(0)


def window_means(signal: np.ndarray, window: int) -> np.ndarray:
    """Mean of a per-row signal over consecutive non-overlapping windows of `window` rows
    (a persistent fault is judged on a stretch of samples, not one): (n,) -> (n // window,)."""
    n = len(signal) // window * window
    return signal[:n].reshape(-1, window).mean(1)


def contiguous_windows(n_rows: int, window: int, max_rows: int, rng: np.random.Generator) -> np.ndarray:
    """Row indices of up to max_rows // window random whole windows, in recorded order."""
    n_win = n_rows // window
    if n_win == 0:
        return np.arange(n_rows)
    pick = np.sort(rng.choice(n_win, min(n_win, max(1, max_rows // window)), replace=False))
    return (pick[:, None] * window + np.arange(window)).ravel()


def flatline(x: np.ndarray, window: int, noise_floor_pa: float = 1.0) -> np.ndarray:
    """Per window of consecutive rows x (n, C) Pa: -log of the smallest channel's std
    (plus a floor). A live barometer always shows its noise; a dead or stuck one is flat."""
    n = len(x) // window * window
    w = x[:n].astype(np.float64).reshape(-1, window, x.shape[1])
    return -np.log(w.std(1).min(1) + noise_floor_pa)


def rest_offset(x: np.ndarray, window: int) -> np.ndarray:
    """Per window of contact-free rows x (n, C) Pa (tared): the largest |mean| over
    channels, in Pa. A drifted baseline shows up as a rest reading away from 0."""
    n = len(x) // window * window
    return np.abs(x[:n].astype(np.float64).reshape(-1, window, x.shape[1]).mean(1)).max(1)
