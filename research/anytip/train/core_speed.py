"""How fast this process's CPU runs the product a tiny network's training is made of.

Most of a unit network's (8-12-64-64-5) arithmetic in a training step is the 64-by-64 layer's forward
and backward products at the batch's 256 rows; the products are 53-61% of torch's step, the rest small
kernels' passes and the Python between calls (research log entries 172, 175), which a faster clock
shortens as well. One network on a CPU now steps compiled (`train.compiled_steps`, entry 204), whose
products are OpenBLAS's, not the kernel timed here: the probe still reads the core's speed. The same
single-core code ran `anytip calibrate` 1.44 times slower on one day than on another (entry 168), so
a calibration's seconds say little without the speed of the core that spent them. `core_gflops` times
that product alone, with torch's own kernel: a reference workload that does not depend on this
package's code, recorded beside a calibration's time (`calibration.json`'s `core_gflops`) so that
times from different machines or days can be set side by side. Within one session on one core a
calibration's seconds still move by a few percent that the product's rate does not see (entry 171),
and on a disturbed day by more (entry 196).
"""

from __future__ import annotations

import time

import torch

REFERENCE_ROWS, REFERENCE_WIDTH = 256, 64  # a step's batch and the deployed shape's hidden width
REFERENCE_FLOP = 2 * REFERENCE_ROWS * REFERENCE_WIDTH * REFERENCE_WIDTH  # one product's multiply-adds x 2


def core_gflops(seconds: float = 0.15, blocks: int = 5) -> float:
    """GFLOP/s of float32 (256, 64) @ (64, 64) products on the CPU, with the threads torch has (one
    under OMP_NUM_THREADS=1, as the calibrate time is measured): the fastest of `blocks` timed blocks
    of about `seconds / blocks` each, after one untimed block. The fastest, because a block that
    another process interrupts reads slow, never fast."""
    if seconds <= 0 or blocks < 1:
        raise ValueError(f"seconds must be > 0 and blocks >= 1, got {seconds} and {blocks}")
    g = torch.Generator().manual_seed(0)
    a = torch.randn(1, REFERENCE_ROWS, REFERENCE_WIDTH, generator=g)
    b = torch.randn(1, REFERENCE_WIDTH, REFERENCE_WIDTH, generator=g)
    out = torch.empty(1, REFERENCE_ROWS, REFERENCE_WIDTH)
    n = _products_in(seconds / blocks, a, b, out)
    best = 0.0
    for _ in range(blocks):
        tick = time.perf_counter()
        for _ in range(n):
            torch.bmm(a, b, out=out)
        best = max(best, REFERENCE_FLOP * n / (time.perf_counter() - tick) / 1e9)
    return best


def _products_in(seconds: float, a: torch.Tensor, b: torch.Tensor, out: torch.Tensor) -> int:
    """How many products fill about `seconds` on this core (at least 10), from an untimed block that
    also warms the kernel up."""
    n, tick = 0, time.perf_counter()
    while n < 10 or time.perf_counter() - tick < seconds:
        torch.bmm(a, b, out=out)
        n += 1
    return n
