"""Moving-average filters for sensor streams: causal (online) and zero-phase (offline, the paper's Fig. 6).

The zero-phase filter runs a causal moving average of `window` samples forward, then
backward, with scipy.signal.filtfilt's edge handling (odd extension by 3 * window
samples, each pass started from the steady state of its first value), so it equals
`filtfilt(ones(window) / window, [1], x)`. Its effective kernel is a triangle of
2 window - 1 samples centred on the output: no delay, but it needs window - 1 future
samples, so it cannot run online. A causal moving average of the same window delays
the signal by (window - 1) / 2 samples instead. Arrays are (N, ...) along `axis`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy.signal import lfilter

from anytip.errors import AnytipError


def check_window(window: int) -> int:
    """`window` as an int >= 1, else an AnytipError naming it."""
    if isinstance(window, bool) or not isinstance(window, (int, np.integer)) or window < 1:
        raise AnytipError(f"moving-average window must be an integer >= 1 samples, got {window!r}")
    return int(window)


def _steady_causal(x: np.ndarray, window: int) -> np.ndarray:
    """Causal moving average along axis 0, as if x[0] had been held before the start."""
    b = np.full(window, 1.0 / window)
    # FIR state after an infinite run of x[0]: zi[j] = (window - 1 - j) / window * x[0]
    zi = np.arange(window - 1, 0, -1, dtype=float).reshape(-1, *[1] * (x.ndim - 1)) / window
    return lfilter(b, [1.0], x, axis=0, zi=zi * x[:1])[0]


def causal_moving_average(x: ArrayLike, window: int, axis: int = 0) -> np.ndarray:
    """Online moving average: y[n] = mean(x[n - window + 1 .. n]), x[0] held before the start.

    Same shape as x; delays a slow signal by (window - 1) / 2 samples.
    """
    window = check_window(window)
    x = np.moveaxis(np.asarray(x, dtype=float), axis, 0)
    if x.shape[0] < 1:
        raise AnytipError("causal_moving_average: the signal is empty")
    return np.moveaxis(_steady_causal(x, window), 0, axis)


def _odd_extend(x: np.ndarray, n: int) -> np.ndarray:
    """x with n samples reflected through each end point (filtfilt's padtype='odd'), axis 0."""
    head = 2.0 * x[:1] - x[n:0:-1]
    tail = 2.0 * x[-1:] - x[-2 : -n - 2 : -1]
    return np.concatenate([head, x, tail])


def zero_phase_moving_average(x: ArrayLike, window: int, axis: int = 0) -> np.ndarray:
    """Forward-backward moving average of `window` samples (like scipy.signal.filtfilt).

    Same shape as x; needs more than 3 * window samples along `axis` (filtfilt's padding).
    """
    window = check_window(window)
    x = np.moveaxis(np.asarray(x, dtype=float), axis, 0)
    pad = 3 * window
    if x.shape[0] <= pad:
        raise AnytipError(f"zero_phase_moving_average: a window of {window} needs more than "
                          f"{pad} samples, got {x.shape[0]}")
    forward = _steady_causal(_odd_extend(x, pad), window)
    both = _steady_causal(forward[::-1], window)[::-1]
    return np.moveaxis(both[pad:-pad], 0, axis)


def causal_delay_s(window: int, rate_hz: float) -> float:
    """Group delay (s) of a causal moving average of `window` samples at `rate_hz`."""
    return (check_window(window) - 1) / 2.0 / _check_rate(rate_hz)


def zero_phase_lookahead_s(window: int, rate_hz: float) -> float:
    """Future signal (s) a forward-backward moving average of `window` samples needs per output."""
    return (check_window(window) - 1) / _check_rate(rate_hz)


def _check_rate(rate_hz: float) -> float:
    if not np.isfinite(rate_hz) or rate_hz <= 0:
        raise AnytipError(f"sample rate must be > 0 Hz, got {rate_hz!r}")
    return float(rate_hz)
