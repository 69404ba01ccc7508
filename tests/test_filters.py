"""Moving-average filters: the zero-phase one equals scipy's filtfilt; delays and errors."""

import numpy as np
import pytest
from scipy.signal import filtfilt

from anytip.analysis.filters import (
    causal_delay_s,
    causal_moving_average,
    zero_phase_lookahead_s,
    zero_phase_moving_average,
)
from anytip.errors import AnytipError


def noisy(n=400, cols=5, seed=0):
    rng = np.random.default_rng(seed)
    return np.sin(np.linspace(0, 12, n))[:, None] * 10 + rng.standard_normal((n, cols)).cumsum(0)


@pytest.mark.parametrize("window", [2, 7, 15])
def test_zero_phase_equals_filtfilt(window):
    x, b = noisy(), np.ones(window) / window
    np.testing.assert_allclose(zero_phase_moving_average(x, window), filtfilt(b, [1.0], x, axis=0),
                               rtol=0, atol=1e-10)
    np.testing.assert_allclose(zero_phase_moving_average(x.T, window, axis=1),
                               filtfilt(b, [1.0], x.T, axis=1), rtol=0, atol=1e-10)
    short = x[: 3 * window + 1, 0]  # the shortest signal filtfilt takes
    np.testing.assert_allclose(zero_phase_moving_average(short, window), filtfilt(b, [1.0], short),
                               rtol=0, atol=1e-10)


def test_zero_phase_keeps_a_symmetric_peak_in_place_and_causal_moves_it():
    x = np.exp(-0.5 * ((np.arange(301) - 150) / 12.0) ** 2)
    assert np.argmax(zero_phase_moving_average(x, 15)) == 150
    assert np.argmax(causal_moving_average(x, 15)) == 157


def test_causal_moving_average_delays_a_ramp_by_half_the_window():
    x = np.arange(100.0)
    y = causal_moving_average(x, 7)
    np.testing.assert_allclose(y[6:], x[6:] - 3.0)
    assert y[0] == 0.0  # x[0] is held before the start: no jump from zero
    assert causal_delay_s(7, 200.0) == pytest.approx(0.015)
    assert causal_delay_s(15, 200.0) == pytest.approx(0.035)
    assert zero_phase_lookahead_s(15, 200.0) == pytest.approx(0.070)


def test_window_one_and_constants_pass_unchanged():
    x = noisy(60, 2)
    np.testing.assert_array_equal(zero_phase_moving_average(x, 1), x)
    np.testing.assert_array_equal(causal_moving_average(x, 1), x)
    np.testing.assert_allclose(zero_phase_moving_average(np.full(80, 3.5), 15), 3.5)


@pytest.mark.parametrize("window", [0, -3, 2.5, True])
def test_bad_window_is_named(window):
    with pytest.raises(AnytipError, match=f"window must be an integer >= 1 samples, got {window!r}"):
        zero_phase_moving_average(noisy(), window)
    with pytest.raises(AnytipError, match="window"):
        causal_moving_average(noisy(), window)


def test_too_short_signal_and_bad_rate():
    with pytest.raises(AnytipError, match="a window of 15 needs more than 45 samples, got 45"):
        zero_phase_moving_average(np.zeros(45), 15)
    with pytest.raises(AnytipError, match="sample rate must be > 0 Hz, got 0.0"):
        causal_delay_s(7, 0.0)
