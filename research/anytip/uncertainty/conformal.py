"""Split conformal intervals, per output.

Scores on a calibration set exchangeable with the test rows give, for miscoverage alpha,
the finite-sample quantile q = the ceil((n + 1)(1 - alpha))-th smallest score of n (the
empirical ceil((n + 1)(1 - alpha)) / n quantile); the interval mu +- q * scale then covers
a new row with probability >= 1 - alpha. scale = 1 is the absolute-residual score; scale =
a predicted sigma is the normalised score |y - mu| / sigma.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from scipy.stats import gmean


def conformal_quantile(scores: np.ndarray, alpha: float) -> np.ndarray:
    """Finite-sample conformal quantile of scores (n, d) per column -> (d,).

    Returns inf where ceil((n + 1)(1 - alpha)) > n (too few rows for that level).
    """
    n = scores.shape[0]
    rank = math.ceil((n + 1) * (1 - alpha))
    if rank > n:
        return np.full(scores.shape[1], np.inf)
    return np.sort(scores, axis=0)[rank - 1]


def residual_halfwidth(residuals: np.ndarray, level: float) -> np.ndarray:
    """Half-width per output (d,) of intervals at nominal `level` from out-of-sample residuals
    (n, d): the conformal quantile of their absolute values."""
    return conformal_quantile(np.abs(residuals), 1.0 - level)


def needed_halfwidths(residuals: np.ndarray, coverages: Sequence[float]) -> np.ndarray:
    """(len(coverages), d): per output, the half-width at which intervals pred +- h cover each
    share of rows with residuals (n, d) (the empirical quantiles of |residual|, interpolated): an
    interval narrower than the first row covers less than coverages[0] of them."""
    return np.quantile(np.abs(residuals), np.asarray(coverages, dtype=float), axis=0)


def fleet_factor(own: np.ndarray, observed: np.ndarray) -> np.ndarray:
    """What the fleet knows about a half-width from a unit's own plan: over units whose test
    rows are labeled (validation units), the geometric mean per output of the half-width the
    test rows needed (observed, (U, d), e.g. `residual_halfwidth` of their test residuals)
    over the one the plan's out-of-fold residuals gave (own, (U, d)) -> (d,). A new unit's
    own half-width times it is the fleet-corrected half-width; 1 leaves it as it is."""
    own, observed = np.asarray(own, dtype=float), np.asarray(observed, dtype=float)
    if own.shape != observed.shape or own.ndim != 2 or not len(own):
        raise ValueError(f"own {own.shape} and observed {observed.shape} half-widths must both be (U > 0, d)")
    both = np.concatenate([own, observed])
    if not (np.isfinite(both).all() and (both > 0).all()):
        raise ValueError("half-widths must be finite and positive to form a fleet factor")
    return np.asarray(gmean(observed / own, axis=0))


def scores_of(mu: np.ndarray, y: np.ndarray, scale: np.ndarray | None = None) -> np.ndarray:
    """Nonconformity |y - mu| / scale, all (n, d); scale None is the absolute residual."""
    r = np.abs(y - mu)
    return r if scale is None else r / scale


def interval(mu: np.ndarray, q: np.ndarray, scale: np.ndarray | None = None
             ) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds (n, d) of mu +- q * scale."""
    half = q if scale is None else q * scale
    return mu - half, mu + half


def coverage(lo: np.ndarray, hi: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Fraction of rows with lo <= y <= hi, per column: (n, d) -> (d,)."""
    return ((y >= lo) & (y <= hi)).mean(0)


def width(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Mean interval width per column (n, d) -> (d,), in the output's unit."""
    return (hi - lo).mean(0)


def mapie_halfwidth(mu: np.ndarray, y_cal: np.ndarray, mu_cal: np.ndarray,
                    confidence: float) -> np.ndarray:
    """Reference: MAPIE's split conformal (absolute residual, prefit) per output column.

    mu (n, d) test predictions, mu_cal, y_cal (n_cal, d): returns the mean half-width of
    MAPIE's intervals per column (d,). The prefit point predictor is a lookup of the
    given predictions, so MAPIE sees exactly the residuals the own code sees.
    """
    from mapie.regression import SplitConformalRegressor

    out = []
    for k in range(mu.shape[1]):
        table = np.concatenate([mu_cal[:, k], mu[:, k]])
        est = _Lookup(table)
        idx_cal = np.arange(len(mu_cal), dtype=float)[:, None]
        idx_test = np.arange(len(mu_cal), len(table), dtype=float)[:, None]
        scr = SplitConformalRegressor(est, confidence_level=confidence, prefit=True)
        scr.conformalize(idx_cal, y_cal[:, k])
        _, pis = scr.predict_interval(idx_test)
        out.append(float(np.mean(pis[:, 1, 0] - pis[:, 0, 0]) / 2))
    return np.array(out)


class _Lookup:
    """A fitted scikit-learn-style regressor whose input is a row index into `table`."""

    def __init__(self, table: np.ndarray):
        self.table = table
        self.fitted_ = True
        self.n_features_in_ = 1

    def fit(self, X: np.ndarray, y: np.ndarray) -> _Lookup:
        return self

    def predict(self, X: np.ndarray) -> np.ndarray:
        return self.table[np.asarray(X)[:, 0].astype(int)]

    def get_params(self, deep: bool = True) -> dict:
        return {}
