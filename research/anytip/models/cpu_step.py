"""One ReLU network's mean-squared-error gradients on a CPU, by numpy.

A unit's own network (`anytip calibrate`) trains alone: one network of the deployed shape, about
20,000 steps of 256 rows on one core. At that size a step is mostly the cost of each call, not its
arithmetic: torch's products cost 4-14 us a call where OpenBLAS's (numpy's) cost 2-9 us at the same
shapes. `NumpyGrads` computes the chain rule of `BatchedMLP.mse_grads`' written-out torch path with
numpy's products and torch's ReLU passes (2-4 us, numpy's maximum 7 us), both on buffers made once,
reading and writing the network's own weight and gradient memory: a step's gradients in about 0.8
of torch's time in a calibration (research log entry 196). They equal autograd's within float32
rounding, as the torch path's do (tests/test_models_mlp.py holds both to the rounding bound).

OpenBLAS would spread a product of this size over every core and lose more than it gains (a third
slower on two cores): a training loop that takes this path runs under `one_blas_thread()`.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Sequence

import numpy as np
import torch
from threadpoolctl import threadpool_limits
from torch import Tensor


def numpy_serves(n_models: int, activation: str, output_activation: str | None) -> bool:
    """Whether `NumpyGrads` computes these networks' step (where their rows are float32 on a CPU): one
    ReLU network without an output activation."""
    return n_models == 1 and activation == "relu" and output_activation is None


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """numpy's BLAS held to one thread for the block (a tiny product loses on several)."""
    with threadpool_limits(limits=1, user_api="blas"):
        yield


class NumpyGrads:
    """The gradients of one ReLU network's mean squared error on batches of `batch` rows.

    `params`: the network's float32 CPU weights, its `layers` weights (1, in, out), then their biases
    (1, 1, out); their gradients are written in place into tensors of the weights' own layout, which
    `grads` holds (in `params`' order) and the caller sets as the weights' `.grad`. Activations and
    back-propagated errors live in buffers made here once, so a step allocates nothing but the loss."""

    def __init__(self, params: Sequence[Tensor], layers: int, batch: int):
        self.batch = batch
        self.params = tuple(params)
        self.ptrs = tuple(p.data_ptr() for p in self.params)
        weights, biases = self.params[:layers], self.params[layers:]
        self.W = [w.detach().numpy()[0] for w in weights]  # (in, out) views of the weights' memory
        self.WT = [w.T for w in self.W]
        self.b = [b.detach().numpy()[0, 0] for b in biases]  # (out,)
        self.grads = [torch.zeros_like(p) for p in self.params]
        self.gW = [g.numpy()[0] for g in self.grads[:layers]]
        self.gb = [g.numpy()[0, 0] for g in self.grads[layers:]]
        self.h = [np.empty((batch, w.shape[1]), np.float32) for w in self.W]  # each layer's output
        self.back = [np.empty((batch, w.shape[0]), np.float32) for w in self.W]  # error at its input
        # the same memory as tensors: torch's ReLU passes cost 2-4 us where numpy's maximum costs 7
        self.h_t = [torch.from_numpy(h) for h in self.h]
        self.back_t = [torch.from_numpy(b) for b in self.back]
        self.ones = np.ones(batch, np.float32)
        self.scale = np.float32(2 / (batch * self.W[-1].shape[1]))  # d mean / d error, as autograd's

    def current(self, params: Sequence[Tensor], batch: int) -> bool:
        """Whether these buffers still serve `params`: the same batch, weights and weight memory."""
        return batch == self.batch and len(params) == len(self.params) and all(
            p is q and p.data_ptr() == ptr for p, q, ptr in zip(params, self.params, self.ptrs, strict=True))

    def __call__(self, x: Tensor, y: Tensor) -> Tensor:
        """The mean squared error (1,) of rows x (1, batch, in) against y (1, batch, out), with its
        gradients left in `grads`."""
        h, target = x.detach().numpy()[0], y.detach().numpy()[0]
        inputs, last = [], len(self.W) - 1
        for k, (W, b, out) in enumerate(zip(self.W, self.b, self.h, strict=True)):
            inputs.append(h)
            np.matmul(h, W, out=out)
            np.add(out, b, out=out)
            if k < last:
                self.h_t[k].relu_()
            h = out
        err = np.subtract(h, target, out=h)
        flat = err.reshape(-1)
        loss = torch.from_numpy(np.array([np.dot(flat, flat) / flat.size], np.float32))
        g = np.multiply(err, self.scale, out=err)
        for k in range(last, -1, -1):
            a = inputs[k]
            np.matmul(a.T, g, out=self.gW[k])
            np.matmul(self.ones, g, out=self.gb[k])
            if k > 0:  # back through W and the ReLU that made a (autograd's own ReLU backward)
                back, back_t = self.back[k], self.back_t[k]
                np.matmul(g, self.WT[k], out=back)
                torch.ops.aten.threshold_backward.grad_input(back_t, self.h_t[k - 1], 0, grad_input=back_t)
                g = back
        return loss
