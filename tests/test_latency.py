"""Latency by cross-correlation: known delays recovered to sub-sample precision; budget parts."""

import numpy as np
import pytest

from anytip.analysis.budget import measure_chains
from anytip.analysis.latency import estimate_delay, hold_delay_s
from anytip.analysis.stream import Stream
from anytip.errors import AnytipError

RNG = np.random.default_rng(7)
FREQ, PHASE, AMP = RNG.uniform(0.2, 6.0, 12), RNG.uniform(0, 2 * np.pi, 12), RNG.uniform(0.5, 1.0, 12)


def signal(t):
    """A band-limited test signal (0.2-6 Hz), defined at any time t (s)."""
    return (AMP * np.sin(2 * np.pi * FREQ * np.asarray(t)[:, None] + PHASE)).sum(axis=1)


def streams(delay, seconds=15.0, noise=0.1, t0=0.0, seed=0):
    """Truth at 1 kHz and an estimate at 200 Hz that shows the truth `delay` s late, both noisy."""
    rng = np.random.default_rng(seed)
    t_truth = np.arange(int(seconds * 1000)) / 1000
    t_est = t0 + np.arange(int(seconds * 200) - 2) / 200
    truth = signal(t_truth) + noise * rng.standard_normal(len(t_truth))
    return truth, signal(t_est - delay) + noise * rng.standard_normal(len(t_est))


@pytest.mark.parametrize("delay_ms", [0.0, 0.3, 2.5, 4.2, 7.0, 12.9, 37.6, -3.1])
def test_known_delays_within_half_a_millisecond(delay_ms):
    truth, est = streams(delay_ms / 1e3, seed=int(abs(delay_ms) * 10))
    got = estimate_delay(truth, 1000.0, est, 200.0)
    assert abs(got * 1e3 - delay_ms) <= 0.5


def test_precision_is_well_below_a_sample_without_noise():
    for delay_ms in (1.37, 8.61):
        truth, est = streams(delay_ms / 1e3, noise=0.0)
        assert abs(estimate_delay(truth, 1000.0, est, 200.0) * 1e3 - delay_ms) < 0.1


def test_a_late_start_and_a_hold_are_seen():
    truth, est = streams(0.004, t0=0.0123)
    assert estimate_delay(truth, 1000.0, est, 200.0, estimate_t0_s=0.0123) == pytest.approx(0.004, abs=5e-4)
    held = estimate_delay(truth, 1000.0, est, 200.0, estimate_t0_s=0.0123, hold="zoh", upsample=10)
    assert held == pytest.approx(0.004 + hold_delay_s(200.0), abs=5e-4)


def test_chains_add_hold_inference_and_causal_filter_delays():
    truth, fz = streams(0.002, noise=0.02)
    n = len(truth)
    stream = Stream(np.stack([truth * 0, truth * 0, truth], 1), np.zeros((n, 2)), np.zeros((len(fz), 8)),
                    1000.0, 5)
    est = np.zeros((len(fz), 5))
    est[:, 2] = fz
    chains = {c.name: c for c in measure_chains(stream, est, 0.0007, [7, 15], 0.1)}
    expected = {"sensor": 2.0, "device": 2.0 + 2.5 + 0.7, "device + causal MA 7": 2.0 + 2.5 + 0.7 + 15.0,
                "device + causal MA 15": 2.0 + 2.5 + 0.7 + 35.0, "zero-phase MA 7 (offline)": 2.0,
                "zero-phase MA 15 (offline)": 2.0}
    for name, ms in expected.items():
        assert chains[name].latency_s * 1e3 == pytest.approx(ms, abs=0.5), name
    assert not chains["zero-phase MA 7 (offline)"].online and chains["device"].online


def test_budget_parts():
    assert hold_delay_s(200.0) == pytest.approx(2.5e-3)


def test_inference_time_of_the_paper_mlp_on_the_microcontroller():
    """Instructions of the compiled export (emulated, or estimated where the toolchain is
    missing) times the budget's cycles per instruction, at its clock."""
    from types import SimpleNamespace

    from anytip.models.mlp import MLPConfig
    from anytip.pipelines.impulse_ratio import Options, inference_cost

    ctx = SimpleNamespace(spec=SimpleNamespace(model=MLPConfig()))
    inf = inference_cost(ctx, Options())
    assert inf["macs"] == 5280 and 2.5 < inf["instructions"] / inf["macs"] < 3.5
    assert inf["seconds"] == pytest.approx(inf["instructions"] * 1.2 / 72e6, rel=1e-3)


def test_bad_input_is_named():
    truth, est = streams(0.0, seconds=2.0)
    with pytest.raises(AnytipError, match="signals too short for max_delay_s=0.5"):
        estimate_delay(truth, 1000.0, est, 200.0, max_delay_s=0.5)
    with pytest.raises(AnytipError, match="max_delay_s must be > 0, got -0.1"):
        estimate_delay(truth, 1000.0, est, 200.0, max_delay_s=-0.1)
    with pytest.raises(AnytipError, match="estimate_rate_hz must be > 0, got 0"):
        estimate_delay(truth, 1000.0, est, 0)
    with pytest.raises(AnytipError, match=r"truth must be a 1-D signal, got shape \(2000, 1\)"):
        estimate_delay(truth[:, None], 1000.0, est, 200.0)
    with pytest.raises(AnytipError, match="upsample must be an integer >= 1, got 0"):
        estimate_delay(truth, 1000.0, est, 200.0, upsample=0)
    with pytest.raises(AnytipError, match="hold must be 'linear' or 'zoh'"):
        estimate_delay(truth, 1000.0, est, 200.0, hold="cubic")
