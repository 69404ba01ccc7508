"""A baseline-drift detector a deployed unit can afford: its tared rest reading.

With nothing touching the dome, tared pressures should sit at zero within noise. They do
not quite: after each unloading the rubber relaxes, so the rest reading undershoots by
0.5-3 kPa and recovers over seconds, and the barometers' offsets follow their
temperature. Both are predictable from what the unit already reads, so each channel c gets
a linear model of its rest reading,

    rest_c ~ sum_j [w_cj * ewma_tau_j(p_c) + v_cj * ewma_tau_j(max(p_c, 0)^2 / s)] + w_cT * dT_c + b_c,

with exponentially weighted means of its own tared pressure p_c and of its square over
every row (time constants `TAUS_ROWS`; the square for channels whose rubber relaxes
nonlinearly, e.g. over a void) and its die temperature change dT_c since tare, fitted on the
contact-free rows of the unit's calibration streams (the lab's force sensor says which).

On the unit, the residual r_c = p_c - rest_c is about 0 at rest plus the drift, and large
and positive in contact. The unit does not need to know when it is at rest: the lowest
residual of each channel over a block of `block_rows` rows (longer than any press, so
every block holds a release) is its rest residual, and a drift moves it by the drift,
whatever the model would call contact. The state is the median of the last 5 block minima
(a single deep undershoot the linear model misses does not move it). The detector reports
the Mahalanobis distance of the state from its clean mean, learnt on calibration rows. A
unit that is never released reads as contact, i.e. is flagged too.

State on the unit: C * (2 len(TAUS_ROWS) + 6) floats (EWMAs, the current block's minimum and
the last 5); parameters C * (2 len(TAUS_ROWS) + 2) weights, C means and a C x C precision.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from scipy.signal import lfilter
from scipy.stats import chi2

from anytip.uncertainty.detect import mahalanobis

TAUS_ROWS = (20, 100, 400, 2000)  # 0.1, 0.5, 2 and 10 s at 200 Hz
SQUARE_SCALE_PA = 10_000.0  # p^2 / this keeps the squared regressors near the linear ones


def ewma(x: np.ndarray, tau_rows: float) -> np.ndarray:
    """Exponentially weighted mean along rows, starting from 0: (n, ...) -> (n, ...)."""
    a = 1.0 / tau_rows
    return lfilter([a], [1.0, a - 1.0], x, axis=0)


def block_minimum(x: np.ndarray, block_rows: int, n_blocks: int = 5) -> np.ndarray:
    """Per channel, the median of the lowest values of x (n, C) in each of the last
    `n_blocks` whole blocks of `block_rows` rows (fewer at the start; within the first block,
    its running minimum): (n, C). The median ignores a single block's deep undershoot."""
    n, C = x.shape
    nb = -(-n // block_rows)
    pad = np.full((nb * block_rows - n, C), np.inf)
    blocks = np.concatenate([x, pad]).reshape(nb, block_rows, C)
    lows = blocks.min(1)  # (nb, C)
    state = np.empty((nb, C))
    for b in range(1, nb):
        state[b] = np.median(lows[max(0, b - n_blocks):b], axis=0)
    out = np.broadcast_to(state[:, None], blocks.shape).copy()
    out[0] = np.minimum.accumulate(blocks[0], axis=0)
    return out.reshape(-1, C)[:n]


def shrunk_covariance(states: np.ndarray, shrink: float = 0.5, min_std_pa: float = 20.0) -> np.ndarray:
    """Covariance (C, C) of clean states (m, C) Pa, halfway to its diagonal, with a floor on
    each channel's std. Block minima change only once per block, so a short calibration holds
    few independent states; the shrinkage and the floor keep the distance from trusting them
    too much."""
    cov = np.cov(states, rowvar=False)
    cov = (1 - shrink) * cov + shrink * np.diag(np.diag(cov))
    return cov + np.diag(np.maximum(min_std_pa ** 2 - np.diag(cov), 0.0))


def features(pressure: np.ndarray, temperature: np.ndarray) -> np.ndarray:
    """Per-channel regressors of the rest reading: (n, C) Pa and (n, C) degC -> (n, C, F),
    F = 2 len(TAUS_ROWS) + 2 (EWMAs of p and of max(p, 0)^2, temperature change, 1)."""
    parts = [ewma(pressure, t) for t in TAUS_ROWS]
    sq = np.maximum(pressure, 0.0) ** 2 / SQUARE_SCALE_PA
    parts += [ewma(sq, t) for t in TAUS_ROWS]
    parts += [temperature, np.ones_like(pressure)]
    return np.stack(parts, -1)


@dataclass
class RestDriftDetector:
    """weights (C, F) of the rest-reading model; mean (C,) Pa and precision (C, C) 1/Pa^2
    of the clean state; block_rows the block length; limit the distance that flags a unit
    (the `LIMIT_QUANTILE` of the clean calibration distances, at least that of a chi
    distribution with C degrees of freedom)."""

    weights: np.ndarray
    mean: np.ndarray
    precision: np.ndarray
    block_rows: int
    limit: float = np.inf

    LIMIT_QUANTILE = 0.999

    @staticmethod
    def fit_weights(feats: Sequence[np.ndarray], pressure: Sequence[np.ndarray],
                    rows: Sequence[np.ndarray], ridge: float = 1e-6) -> np.ndarray:
        """Least squares per channel on the rest rows `rows` (bool masks) of each stream."""
        A = np.concatenate([f[r] for f, r in zip(feats, rows, strict=True)])  # (m, C, F)
        y = np.concatenate([p[r] for p, r in zip(pressure, rows, strict=True)])  # (m, C)
        if len(A) < 10 * A.shape[2]:
            raise ValueError(f"{len(A)} calibration rest rows: too few to fit the rest-reading model")
        w = np.empty(A.shape[1:])
        for c in range(A.shape[1]):
            G = A[:, c].T @ A[:, c]
            G += ridge * np.trace(G) / len(G) * np.eye(len(G))
            w[c] = np.linalg.solve(G, A[:, c].T @ y[:, c])
        return w

    @classmethod
    def fit(cls, streams: Sequence[tuple[np.ndarray, np.ndarray]], rest_rows: Sequence[np.ndarray],
            stat_rows: Sequence[np.ndarray], block_rows: int, starts: Sequence[int] | None = None
            ) -> RestDriftDetector:
        """Fit on clean streams (pressure (n, C) Pa, temperature (n, C) degC): the rest-reading
        model on the contact-free rows `rest_rows`, then the clean state's mean and covariance
        on the rows `stat_rows` (bool masks (n,) per stream); `starts` as in `state`."""
        starts = [0] * len(streams) if starts is None else starts
        feats = [features(p, t) for p, t in streams]
        w = cls.fit_weights(feats, [p for p, _ in streams], rest_rows)
        det = cls(w, np.zeros(w.shape[0]), np.eye(w.shape[0]), block_rows)
        parts = zip(streams, feats, stat_rows, starts, strict=True)
        states = np.concatenate([det.state(s, f, k)[r] for s, f, r, k in parts])
        mean, precision = states.mean(0), np.linalg.inv(shrunk_covariance(states))
        dist = mahalanobis(states - mean, precision)
        gauss = np.sqrt(chi2.ppf(cls.LIMIT_QUANTILE, len(mean)))  # the floor a short calibration gets
        return cls(w, mean, precision, block_rows, float(max(np.quantile(dist, cls.LIMIT_QUANTILE), gauss)))

    def residual(self, stream: tuple[np.ndarray, np.ndarray], feats: np.ndarray | None = None) -> np.ndarray:
        """Tared pressure minus the modelled rest reading (n, C) Pa."""
        pressure, temperature = stream
        f = features(pressure, temperature) if feats is None else feats
        return pressure - np.einsum("ncf,cf->nc", f, self.weights)

    def state(self, stream: tuple[np.ndarray, np.ndarray], feats: np.ndarray | None = None,
              start: int = 0) -> np.ndarray:
        """The state (n, C) Pa after every row of a stream whose rows from `start` on are
        watched (the rows before it, e.g. the tare, are left out; the state is the clean
        mean until the first watched row)."""
        r = self.residual(stream, feats)
        r[:start] = np.inf
        out = block_minimum(r, self.block_rows)
        return np.where(np.isfinite(out), out, self.mean)

    def __call__(self, stream: tuple[np.ndarray, np.ndarray], start: int = 0) -> np.ndarray:
        """(n,) Mahalanobis distance of the state from its clean mean after every row."""
        return mahalanobis(self.state(stream, start=start) - self.mean, self.precision)

    def rereferenced(self, stream: tuple[np.ndarray, np.ndarray], start: int, rows: np.ndarray
                     ) -> RestDriftDetector:
        """The detector with its clean mean re-learnt on `rows` (n,) bool of a stream: right
        after a power-up and tare, before a slow drift builds up, the unit reads its own clean
        state; the rest model, covariance and limit stay those of the calibration."""
        if not rows.any():  # no reference rows: keep the calibration's mean
            return self
        return replace(self, mean=self.state(stream, start=start)[rows].mean(0))

    def flag(self, stream: tuple[np.ndarray, np.ndarray], start: int = 0) -> np.ndarray:
        """(n,) bool: rows after which the unit reports a drifted baseline."""
        return self(stream, start) > self.limit

    @property
    def cost(self) -> dict[str, int]:
        """Floats of state and parameters, multiply-accumulates per row on the unit."""
        C, F = self.weights.shape
        return {"state": C * (2 * len(TAUS_ROWS) + 6), "parameters": C * F + C + C * C,
                "macs": C * (2 * len(TAUS_ROWS) + F + 1) + C * C + C}
