"""Cross-conformal over patch folds: every non-test patch of a unit calibrates.

A unit's non-test patches are cut into K folds of whole patches. Fold model k (a
heteroscedastic MLP) trains on the other folds, so its residuals on fold k are
out-of-sample; together the K folds give an out-of-fold score for every non-test row, about
five times the calibration patches of a split. A test row and an out-of-fold row are then
exchangeable for the fold model that saw neither, so the unit deploys one fold model and
its interval mu_k +- q scale_k uses q, the conformal quantile of all out-of-fold scores.
The report scores each test row with a fold model drawn at random (the coverage of
deploying any one of them). The mean of the K models would be more accurate than the fold
models that produced the scores, and its intervals over-cover (0.91-0.96 at nominal 0.9 on
a tiny fleet).
"""

from __future__ import annotations

import numpy as np


def patch_folds(patch: np.ndarray, k: int, seed: int) -> np.ndarray:
    """(n,) int fold of each row: whole patches dealt at random to k folds (as even as the
    patch count allows)."""
    cells = np.unique(patch)
    if len(cells) < k:
        raise ValueError(f"{len(cells)} patches cannot make {k} folds")
    order = np.random.default_rng(seed).permutation(cells)
    fold_of = dict(zip(order.tolist(), (np.arange(len(order)) % k).tolist(), strict=True))
    return np.array([fold_of[int(p)] for p in patch], dtype=np.int64)


def out_of_fold(pred: list[tuple[np.ndarray, np.ndarray]], fold: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Means and sigmas (n, d) of each row from the fold model that did not train on it;
    pred[k] = fold model k's (mu, sigma), each (n, d), on all rows."""
    mu = np.empty_like(pred[0][0])
    sigma = np.empty_like(pred[0][1])
    for k, (m, s) in enumerate(pred):
        mu[fold == k], sigma[fold == k] = m[fold == k], s[fold == k]
    return mu, sigma


def pick_fold_model(pred: list[tuple[np.ndarray, np.ndarray]], rng: np.random.Generator
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Each row's mean and sigma (n, d) from one fold model drawn at random per row;
    pred[k] = fold model k's (mu, sigma), each (n, d)."""
    k = rng.integers(len(pred), size=len(pred[0][0]))
    return out_of_fold(pred, k)
