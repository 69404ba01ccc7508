"""Research log entry 175: the unit network's training step, eager against compiled, and its products apart.

One step of `anytip calibrate`'s unit network (the deployed 8-12-64-64-5 ReLU shape, one unit, the recipe's
batch of 256 rows, float32, one thread): `BatchedMLP.mse_grads` (the chain rule written out, eager) against
the same forward and backward written as one function and compiled by `torch.compile` (inductor, the CPU's
C++ backend) in one of four ways. The optimizer's step (`FusedAdam`, eager) is left out of both: it is the
same either way. Prints one line per process:

    python step_cost.py products            # each of the step's products timed apart, and the step
    python step_cost.py VARIANT             # default | cpp_wrapper | max_autotune | cpp_wrapper+max_autotune

A VARIANT line holds the first call's seconds (the compile, or loading it from TORCHINDUCTOR_CACHE_DIR where
an earlier process left it), the compiled and the eager step's microseconds (medians over alternated
blocks) and the compiled gradients' largest difference from the eager ones over each weight's largest
magnitude. `run.sh` runs each variant twice on one cache directory of its own: cold, then warm.
"""

from __future__ import annotations

import statistics
import sys
import time
from collections.abc import Callable

import torch
import torch._inductor.config as inductor_config
from torch import Tensor

from anytip.models.mlp import BatchedMLP, MLPConfig, _bmm

BATCH, BLOCKS, STEPS = 256, 7, 1500  # rows per step; alternated timing blocks of STEPS steps each
VARIANTS = {"default": {}, "cpp_wrapper": {"cpp_wrapper": True},
            "max_autotune": {"mode": "max-autotune-no-cudagraphs"},
            "cpp_wrapper+max_autotune": {"cpp_wrapper": True, "mode": "max-autotune-no-cudagraphs"}}


def per_call_us(f: Callable[[], object], n: int = STEPS) -> float:
    """Microseconds per call of f, over n calls after 50 unmeasured ones."""
    for _ in range(50):
        f()
    start = time.perf_counter()
    for _ in range(n):
        f()
    return (time.perf_counter() - start) / n * 1e6


def written_out(x: Tensor, y: Tensor, *params: Tensor) -> tuple[Tensor, list[Tensor]]:
    """`mse_grads`' forward and backward for a ReLU network as one function of x (U, B, in), y (U, B, out) and
    the weights then the biases: each unit's mean squared error (U,) and the gradients of its sum, in the
    parameters' order."""
    n = len(params) // 2
    Ws, bs = params[:n], params[n:]
    inputs, h = [], x
    for k in range(n):
        inputs.append(h)
        h = torch.baddbmm(bs[k], h, Ws[k])
        if k < n - 1:
            h = h.relu()
    err = h - y
    loss = (err**2).mean(dim=(1, 2))
    g = err * (2 / (err.shape[1] * err.shape[2]))
    grads: list[Tensor] = [g] * (2 * n)
    for k in range(n - 1, -1, -1):
        a = inputs[k]
        grads[k], grads[n + k] = a.transpose(1, 2) @ g, g.sum(1, keepdim=True)
        if k > 0:
            g = (g @ Ws[k].transpose(1, 2)) * (a > 0)
    return loss, grads


def setup() -> tuple[BatchedMLP, Tensor, Tensor, list[Tensor]]:
    """The deployed shape's network (seed 0) and one batch of standardised rows."""
    g = torch.Generator().manual_seed(0)
    model = BatchedMLP(1, MLPConfig(), seed=0)
    x, y = torch.randn(1, BATCH, 8, generator=g), torch.randn(1, BATCH, 5, generator=g)
    return model, x, y, [p.detach() for p in (*model.weights, *model.biases)]


def products() -> None:
    """Each product of one `mse_grads` step timed apart (forward, weight gradient, input gradient per
    layer) and their sum, beside the step."""
    model, x, y, params = setup()
    n = len(params) // 2
    parts: list[str] = []
    total = 0.0
    with torch.no_grad():
        h, acts = x, []
        for k in range(n):
            acts.append(h)
            h = torch.baddbmm(params[n + k], h, params[k]).relu_() if k < n - 1 else h
        for k in range(n):
            W, b, a = params[k], params[n + k], acts[k]
            g = torch.randn(1, BATCH, W.shape[2])
            product = _bmm if k == n - 1 else (lambda a, W, b: torch.baddbmm(b, a, W))
            fwd = per_call_us(lambda W=W, b=b, a=a, product=product: product(a, W, b))
            dw = per_call_us(lambda a=a, g=g: _bmm(a.transpose(1, 2), g).contiguous())
            dx = per_call_us(lambda g=g, W=W: _bmm(g, W.transpose(1, 2))) if k else 0.0
            gflops = 2 * BATCH * W.shape[1] * W.shape[2] / 1e3  # kFLOP per product: over us, GFLOP/s
            parts.append(f"{W.shape[1]}x{W.shape[2]} fwd {fwd:.1f} dW {dw:.1f} dX {dx:.1f} us "
                         f"({gflops / fwd:.0f} GFLOP/s fwd)")
            total += fwd + dw + dx
    step = per_call_us(lambda: model.mse_grads(x, y))
    print("products", " | ".join(parts), f"| products_us {total:.1f} step_us {step:.1f}")


def compiled(variant: str) -> None:
    """One variant's line: first call's seconds, compiled and eager step (us, medians of alternated blocks),
    the gradients' difference."""
    options = dict(VARIANTS[variant])
    inductor_config.cpp_wrapper = bool(options.pop("cpp_wrapper", False))
    model, x, y, params = setup()
    step = torch.compile(written_out, dynamic=False, **options)
    with torch.no_grad():
        start = time.perf_counter()
        loss, grads = step(x, y, *params)
        first_s = time.perf_counter() - start
        eager_loss = model.mse_grads(x, y)
        eager = [p.grad for p in (*model.weights, *model.biases)]
        diff = max(float((a - b).abs().max() / b.abs().max()) for a, b in zip(grads, eager, strict=True))
        diff = max(diff, float((loss - eager_loss).abs().max() / eager_loss.abs().max()))
        times: dict[str, list[float]] = {"compiled": [], "eager": []}
        for block in range(BLOCKS):
            for arm in (("compiled", "eager") if block % 2 == 0 else ("eager", "compiled")):
                f = (lambda: step(x, y, *params)) if arm == "compiled" else (lambda: model.mse_grads(x, y))
                times[arm].append(per_call_us(f))
    c, e = (statistics.median(times[a]) for a in ("compiled", "eager"))
    print(f"variant {variant} first_call_s {first_s:.2f} compiled_us {c:.1f} eager_us {e:.1f} "
          f"ratio {c / e:.3f} grad_rel_diff {diff:.1e}")


if __name__ == "__main__":
    torch.set_num_threads(1)
    products() if sys.argv[1] == "products" else compiled(sys.argv[1])
