"""The reference workload a calibration's time is recorded with (`anytip.train.core_speed`)."""

import time

import pytest
import torch

from anytip.train.core_speed import REFERENCE_FLOP, core_gflops


def test_core_gflops_is_the_products_rate_measured_apart():
    """The probe's rate agrees with the same product timed here by hand: neither a unit slip (FLOP,
    not multiply-adds; GFLOP, not FLOP) nor a block that times nothing gets through. The hand timing
    takes its best of 5 blocks too, and the machines are noisy, so within a factor of 2."""
    a, b = torch.randn(1, 256, 64), torch.randn(1, 64, 64)
    best = 0.0
    for _ in range(5):
        tick = time.perf_counter()
        for _ in range(200):
            torch.bmm(a, b)
        best = max(best, 200 * 2 * 256 * 64 * 64 / (time.perf_counter() - tick) / 1e9)
    probe = core_gflops(seconds=0.1)
    assert REFERENCE_FLOP == 2 * 256 * 64 * 64
    assert best / 2 < probe < best * 2


def test_core_gflops_refuses_an_empty_measurement():
    with pytest.raises(ValueError, match="seconds must be > 0"):
        core_gflops(seconds=0)
    with pytest.raises(ValueError, match="blocks >= 1"):
        core_gflops(blocks=0)
