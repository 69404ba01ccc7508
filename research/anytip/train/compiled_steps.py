"""One ReLU network's training steps on a CPU core, compiled: gradients and Adam in one call.

A unit's own network (`anytip calibrate`) trains alone: one network of the deployed shape, about
20,000 steps of 256 rows on one core, whose arithmetic takes about 90 us a step. Called from Python,
each of a step's dozen products and passes costs 2-14 us of dispatch, and the optimizer and the loop
around them add more: a step took about 265 us in a calibration. `CompiledSteps` runs a stretch of
steps (up to the next evaluation) in one numba-compiled call: the forward pass, the chain rule of the
mean squared error and the Adam (or AdamW) update of every weight, on the network's own weight memory,
with BLAS's products through numba (research log entry 204). Its updates equal torch's fused Adam after
the written-out gradients within float32 rounding (tests/test_compiled_steps.py), not bit for bit.

The compiled code is cached beside this module (numba's `cache=True`; a read-only install caches in
the user's cache directory): the first call of a fresh install compiles it (about 3 s), later
processes load it (about 0.3 s). `compile_now` compiles it for the deployed shape ahead of any
calibration (`make venv` calls it), so that a lab's first calibration does not pay for it.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator, Sequence

import numpy as np
import scipy.linalg.cython_blas  # noqa: F401  numba's products call its BLAS: loaded before any thread limit
import torch
from numba import njit
from threadpoolctl import threadpool_limits
from torch import Tensor

from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.train.recipe import FAST, TrainRecipe

BETAS, EPS = (0.9, 0.999), 1e-8  # torch's Adam defaults, as `make_optimizer`'s


def compiled_serves(model: BatchedMLP, device: torch.device) -> bool:
    """Whether `CompiledSteps` trains `model` on `device`: one ReLU network without an output activation,
    every weight float32 on a CPU."""
    return device.type == "cpu" and model.is_one_relu_network() and all(
        p.is_cpu and p.dtype == torch.float32 for p in model.parameters())


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """BLAS held to one thread for the block: it would spread each of a tiny network's products over every
    core and lose more than it gains (a third slower on two cores)."""
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def compile_now() -> None:
    """Compile the steps (or load them from numba's cache) for networks of the deployed shape's depth, by one
    step at learning rate 0 of a throwaway network: every network of as many layers then loads them."""
    config = MLPConfig()
    steps = CompiledSteps(BatchedMLP(1, config, seed=0), FAST.model_copy(update={"batch_size": 2}))
    steps.run(torch.zeros(1, 1, 2, config.sizes[0]), torch.zeros(1, 1, 2, config.sizes[-1]), [0.0])


class CompiledSteps:
    """Adam (`recipe.optimizer` adam or adamw, its weight decay) on one ReLU network, `recipe.batch_size`
    rows a step, every step of a stretch in one compiled call. Holds the optimizer's state (each weight's
    first and second moments and the step count) and buffers made once."""

    def __init__(self, model: BatchedMLP, recipe: TrainRecipe):
        self.W = tuple(w.detach().numpy()[0] for w in model.weights)  # (in, out), the weights' memory
        self.b = tuple(b.detach().numpy()[0, 0] for b in model.biases)  # (out,)
        self.mW, self.vW = (tuple(np.zeros_like(w) for w in self.W) for _ in range(2))
        self.mb, self.vb = (tuple(np.zeros_like(b) for b in self.b) for _ in range(2))
        B = recipe.batch_size
        self.h = tuple(np.empty((B, w.shape[1]), np.float32) for w in self.W)  # each layer's output
        self.back = tuple(np.empty((B, w.shape[0]), np.float32) for w in self.W)  # error at its input
        self.gW = tuple(np.empty_like(w) for w in self.W)
        self.gb = tuple(np.empty_like(b) for b in self.b)
        self.ones = np.ones(B, np.float32)
        self.weight_decay, self.decoupled = float(recipe.weight_decay), recipe.optimizer == "adamw"
        self.t = 0

    def run(self, x: Tensor, y: Tensor, lrs: Sequence[float]) -> Tensor:
        """Steps on rows x (k, 1, B, in) and y (k, 1, B, out), step i at learning rate lrs[i]; each
        step's mean squared error before its update, summed: (1,)."""
        X, Y = (np.ascontiguousarray(t.numpy()[:, 0]) for t in (x, y))
        if X.shape[1] != len(self.ones) or Y.shape[1] != len(self.ones):
            raise ValueError(f"batches of {X.shape[1]} rows, where the steps were made for {len(self.ones)}")
        loss = _steps(self.W, self.b, self.mW, self.vW, self.mb, self.vb, X, Y, np.asarray(lrs, np.float64),
                      self.t, BETAS[0], BETAS[1], EPS, self.weight_decay, self.decoupled,
                      (self.h, self.back, self.gW, self.gb, self.ones))
        self.t += len(lrs)
        return torch.tensor([loss], dtype=torch.float32)


Arrays = tuple[np.ndarray, ...]


@njit(cache=True)
def _steps(W: Arrays, b: Arrays, mW: Arrays, vW: Arrays, mb: Arrays, vb: Arrays, X: np.ndarray, Y: np.ndarray,
           lrs: np.ndarray, t0: int, beta1: float, beta2: float, eps: float, wd: float, decoupled: bool,
           buffers: tuple[Arrays, Arrays, Arrays, Arrays, np.ndarray]) -> float:
    """len(lrs) steps of Adam on the network (W, b) over batches X (k, B, in), Y (k, B, out): the sum of
    their losses. `buffers`: (layer outputs, input errors, weight and bias gradients, ones (B,))."""
    h, back, gW, gb, ones = buffers
    last = len(W) - 1
    total = 0.0
    for s in range(X.shape[0]):
        a = X[s]
        for k in range(last + 1):
            out = h[k]
            np.dot(a, W[k], out)
            out += b[k]
            if k < last:
                np.maximum(out, np.float32(0), out)
            a = out
        err = h[last]
        err -= Y[s]
        flat, square = err.reshape(-1), 0.0
        for i in range(flat.size):
            square += flat[i] * flat[i]
        total += square / flat.size
        err *= np.float32(2.0 / flat.size)  # d mean / d error
        g = err
        for k in range(last, -1, -1):
            a = X[s] if k == 0 else h[k - 1]
            np.dot(a.T, g, gW[k])
            np.dot(ones, g, gb[k])
            if k > 0:  # back through W and the ReLU that made a
                np.dot(g, W[k].T, back[k])
                e, made = back[k], h[k - 1]
                for i in range(e.shape[0]):
                    for j in range(e.shape[1]):
                        if made[i, j] <= 0:
                            e[i, j] = 0
                g = back[k]
        t = t0 + s + 1
        step, root = lrs[s] / (1 - beta1**t), math.sqrt(1 - beta2**t)
        for k in range(last + 1):
            _adam(W[k].reshape(-1), gW[k].reshape(-1), mW[k].reshape(-1), vW[k].reshape(-1),
                  lrs[s], step, root, beta1, beta2, eps, wd, decoupled)
            _adam(b[k], gb[k], mb[k], vb[k], lrs[s], step, root, beta1, beta2, eps, wd, decoupled)
    return total


@njit(cache=True)
def _adam(p: np.ndarray, g: np.ndarray, m: np.ndarray, v: np.ndarray, lr: float, step: float, root: float,
          beta1: float, beta2: float, eps: float, wd: float, decoupled: bool) -> None:
    """One Adam update of the flat weights p from gradients g, moments m and v, in place, in float32 as
    torch's fused kernel computes it (weight decay added to the gradient, or for AdamW taken off the
    weight)."""
    f32 = np.float32
    lr_, step_, root_, wd_, eps_ = f32(lr), f32(step), f32(root), f32(wd), f32(eps)
    b1, b2 = f32(1 - beta1), f32(beta2)
    c2 = f32(1 - beta2)
    for i in range(p.size):
        grad = g[i]
        if wd != 0:
            if decoupled:
                p[i] -= lr_ * wd_ * p[i]
            else:
                grad += wd_ * p[i]
        m[i] += b1 * (grad - m[i])
        v[i] = v[i] * b2 + c2 * grad * grad
        p[i] -= step_ * m[i] / (math.sqrt(v[i]) / root_ + eps_)
