"""End-to-end latency by cross-correlation, and the parts of a latency budget.

`estimate_delay` finds how far a processed estimate (e.g. 200 Hz) trails a ground-truth
signal (e.g. a 1 kHz force/torque sensor): the estimate is put on the truth's time grid
(linear interpolation between its samples, or a zero-order hold, what a consumer polling
the latest output sees), correlated with the truth over a window of lags, and the peak
is refined by a parabola through its three highest points, which gives sub-sample
precision for signals much slower than the truth's rate. Times in seconds.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy.signal import correlate

from anytip.errors import AnytipError

Hold = Literal["linear", "zoh"]


def _signal(x: ArrayLike, name: str) -> np.ndarray:
    arr = np.asarray(x, dtype=float)
    if arr.ndim != 1:
        raise AnytipError(f"{name} must be a 1-D signal, got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise AnytipError(f"{name} holds NaN or infinite values")
    return arr


def _positive(value: float, name: str) -> float:
    if not np.isfinite(value) or value <= 0:
        raise AnytipError(f"{name} must be > 0, got {value!r}")
    return float(value)


def on_grid(estimate: np.ndarray, rate_hz: float, t0_s: float, times_s: np.ndarray,
            hold: Hold) -> np.ndarray:
    """(T,) the estimate (M,), sampled at t0 + m / rate, read at `times_s` (T,); NaN where undefined.

    linear: interpolation between samples. zoh: each sample holds until the next one.
    """
    pos = (times_s - t0_s) * rate_hz
    if hold == "linear":
        inside = (pos >= 0) & (pos <= len(estimate) - 1)
        return np.where(inside, np.interp(pos, np.arange(len(estimate)), estimate), np.nan)
    if hold == "zoh":
        idx = np.floor(pos + 1e-9).astype(int)  # a sample is visible from its own instant on
        inside = (idx >= 0) & (idx < len(estimate))
        return np.where(inside, estimate[np.clip(idx, 0, len(estimate) - 1)], np.nan)
    raise AnytipError(f"hold must be 'linear' or 'zoh', got {hold!r}")


def estimate_delay(truth: ArrayLike, truth_rate_hz: float, estimate: ArrayLike, estimate_rate_hz: float,
                   max_delay_s: float = 0.1, estimate_t0_s: float = 0.0, hold: Hold = "linear",
                   upsample: int = 1) -> float:
    """Delay (s) of `estimate` behind `truth`; positive when the estimate lags.

    truth (N,) sampled at n / truth_rate_hz; estimate (M,) at estimate_t0_s + m /
    estimate_rate_hz. Both are compared on a grid `upsample` times finer than the truth's
    (the truth interpolated linearly): a zero-order hold read on the truth's own grid
    would only see the ages that grid happens to hit. Lags within +-max_delay_s are
    searched; the estimate is used only where the truth extends max_delay_s beyond it on
    both sides, so every lag compares the same samples (no bias towards zero lag).
    """
    truth, estimate = _signal(truth, "truth"), _signal(estimate, "estimate")
    _positive(truth_rate_hz, "truth_rate_hz")
    _positive(estimate_rate_hz, "estimate_rate_hz")
    if isinstance(upsample, bool) or not isinstance(upsample, (int, np.integer)) or upsample < 1:
        raise AnytipError(f"upsample must be an integer >= 1, got {upsample!r}")
    fs = truth_rate_hz * upsample
    times = np.arange((len(truth) - 1) * upsample + 1) / fs
    truth = np.interp(times, np.arange(len(truth)) / truth_rate_hz, truth)
    max_lag = int(np.ceil(_positive(max_delay_s, "max_delay_s") * fs)) + 1
    seen = on_grid(estimate, estimate_rate_hz, estimate_t0_s, times, hold)
    usable = np.isfinite(seen)
    usable[:max_lag] = usable[len(usable) - max_lag:] = False
    idx = np.flatnonzero(usable)
    if len(idx) < 4 * max_lag:
        raise AnytipError(f"signals too short for max_delay_s={max_delay_s}: {len(idx)} truth samples "
                          f"overlap the estimate away from the ends; need at least {4 * max_lag}")
    start, stop = idx[0], idx[-1] + 1
    seg = seen[start:stop] - np.nanmean(seen[start:stop])
    if np.isnan(seg).any():
        raise AnytipError("the estimate does not cover one contiguous stretch of the truth")
    window = truth[start - max_lag : stop + max_lag]
    # corr[j] = sum_n window[n + j] seg[n]; lag L = max_lag - j
    corr = correlate(window - window.mean(), seg, mode="valid", method="fft")
    j = int(np.argmax(corr))
    j = min(max(j, 1), len(corr) - 2)
    return (max_lag - (j + _parabola_peak(corr[j - 1 : j + 2]))) / fs


def _parabola_peak(c: np.ndarray) -> float:
    """Offset in (-1, 1) of the vertex of the parabola through three points (c[-1], c[0], c[1])."""
    denom = c[0] - 2.0 * c[1] + c[2]
    if denom >= 0:  # not a maximum (flat or convex): keep the sample
        return 0.0
    return float(np.clip(0.5 * (c[0] - c[2]) / denom, -1.0, 1.0))


def hold_delay_s(rate_hz: float) -> float:
    """Mean age (s) of a zero-order-held output that refreshes at rate_hz: half a period."""
    return 0.5 / _positive(rate_hz, "rate_hz")
