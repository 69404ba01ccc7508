"""Post-training quantization for the int8 C export.

Activations are int16 with a static per-channel scale s_a = 1.1 max |a| / 32767 calibrated on
reference rows; the inputs are centred first (q = round((p - in_mean) / s_a), p in Pa), and every
layer's ReLU output feeds the next. Weights are per-output-channel symmetric int8 of the effective
weights diag(s_a) W, rounded with GPTQ's error feedback (Frantar et al., 2023) on the calibration
activations on the best of a few clipped grids per channel (scale refitted by least squares), and
each float bias is corrected by the mean output error the quantization leaves. Then, layer by
layer on the int8 network's own inputs, each channel's float32 mult and bias are refitted by least
squares to the float network's pre-activations (`refit_affine`), and the rounding of every layer
is refined greedily (+-1 moves) against the float network's outputs on the calibration rows
(`refine_rounding`; each move is scored by a rank-one update of the layer's sums, so the 64 x 64
layer is affordable too).
A layer accumulates acc[o] = sum_i q_w[i, o] q_a[i] in int32 and rescales once per channel in
float32: y[o] = acc[o] * mult[o] + bias[o], then ReLU, then round to int16 for the next layer
(the last layer's mult and bias give physical units). `simulate` mirrors the C code.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from anytip.deploy.net import DeployNet, require_relu
from anytip.errors import AnytipError

W_MAX, A_MAX = 127, 32767
HEADROOM = 1.1
# (layer, passes, rows) of the greedy rounding search, in this order: first, last, second, third
REFINE = ((0, 3, 2000), (-1, 2, 2000), (1, 2, 1000), (2, 2, 2000))
DAMP = 0.01  # GPTQ's damping, a fraction of the mean diagonal of X^T X
REFIT = True  # refit each channel's mult and bias (least squares) before the rounding search
CLIP_ALPHAS = (1.0, 0.95, 0.9, 0.85, 0.8, 0.75, 0.7)  # int8 grids tried: scale = alpha max |w| / 127


@dataclass
class QuantLayer:
    """q_w (in, out) int8; mult, bias (out,) float32; relu after the layer."""

    q_w: np.ndarray
    mult: np.ndarray
    bias: np.ndarray
    relu: bool


@dataclass
class QuantNet:
    """in_mean (in,) Pa and in_inv_scale (in,) 1/Pa (float32) quantize the inputs; out_offset (out,)."""

    in_mean: np.ndarray
    in_inv_scale: np.ndarray
    layers: list[QuantLayer]
    out_offset: np.ndarray


def _round_clip(v: np.ndarray, limit: int = A_MAX) -> np.ndarray:
    """Round half away from zero and saturate, as the C code does."""
    r = np.where(v >= 0, np.floor(v + np.float32(0.5)), np.ceil(v - np.float32(0.5)))
    return np.clip(r, -limit, limit)


def _scale(a: np.ndarray) -> np.ndarray:
    """Per-channel int16 scale of activations a (B, d)."""
    return np.maximum(np.abs(a).max(0) * HEADROOM, 1e-12) / A_MAX


def gptq(W: np.ndarray, X: np.ndarray, s_w: np.ndarray) -> np.ndarray:
    """Integer weights (in, out) for W (in, out) with per-output scales s_w, inputs X (B, in).

    Rounds input rows in order and spreads each row's rounding error over the rows still to come,
    weighted by the inverse Hessian of ||X W - X Q||^2 (GPTQ)."""
    H = X.T @ X
    H += DAMP * np.mean(np.diag(H)) * np.eye(len(H)) + 1e-12 * np.eye(len(H))
    U = np.linalg.cholesky(np.linalg.inv(H)).T  # upper Cholesky factor of H^-1
    W, Q = W.copy(), np.zeros_like(W)
    for i in range(W.shape[0]):
        Q[i] = np.clip(np.rint(W[i] / s_w), -W_MAX, W_MAX)
        err = (W[i] - Q[i] * s_w) / U[i, i]
        W[i + 1:] -= np.outer(U[i, i + 1:], err)
    return Q


def _best_grid(Wt: np.ndarray, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per output channel, the int8 grid (scale = alpha max |w| / 127, alpha in CLIP_ALPHAS) whose
    GPTQ rounding, with the scale then refitted by least squares, best reproduces X @ Wt."""
    Z = X @ Wt
    best_err = np.full(Wt.shape[1], np.inf)
    best_q, best_s = np.zeros_like(Wt), np.ones(Wt.shape[1])
    for alpha in CLIP_ALPHAS:
        s_w = alpha * np.maximum(np.abs(Wt).max(0), 1e-30) / W_MAX
        Q = gptq(Wt, X, s_w)
        XQ = X @ Q
        s_fit = np.where((XQ * XQ).sum(0) > 0, (XQ * Z).sum(0) / np.maximum((XQ * XQ).sum(0), 1e-30), s_w)
        err = ((XQ * s_fit - Z) ** 2).sum(0)
        better = err < best_err
        best_err[better], best_q[:, better], best_s[better] = err[better], Q[:, better], s_fit[better]
    return best_q, best_s


def quantize(net: DeployNet, x_cal: np.ndarray, error_scale: np.ndarray | None = None) -> QuantNet:
    """Quantize a folded network; x_cal (B, in) Pa sets activation scales and rounding.

    error_scale (out,): the rounding search weighs output k's error by 1 / error_scale[k]^2
    (default: the output scale; `anytip export` passes the float model's RMSE per output when the
    reference rows have targets, so that each output's relative RMSE increase counts alike)."""
    require_relu(net, "c-int8")
    n_in_max = max(W.shape[0] for W, _ in net.layers)
    if n_in_max * W_MAX * A_MAX >= 2**31:
        raise AnytipError(f"a layer with {n_in_max} inputs could overflow the int32 accumulator")
    x = np.asarray(x_cal, np.float64)
    in_mean = x.mean(0)
    W0, b0 = net.layers[0]
    first = [(W0, b0 + in_mean @ W0)] + net.layers[1:]  # layer 0 sees centred pressures
    h_f = x - in_mean  # the float network's activations
    s_a = _scale(h_f)
    q_a = _round_clip(h_f / s_a)  # the quantized network's activations (integers)
    layers, last, targets = [], len(first) - 1, []
    for k, (W, b) in enumerate(first):
        Wt = W * s_a[:, None]  # acts on integer activations
        Q, s_w = _best_grid(Wt, q_a)
        z_f, z_q = h_f @ W + b, q_a @ (Q * s_w) + b
        b = b + (z_f - z_q).mean(0)  # bias correction
        relu = k < last or net.output_relu
        h_f = np.maximum(z_f, 0) if relu else z_f
        s_next = _scale(h_f) if k < last else np.ones(W.shape[1])
        layers.append(QuantLayer(Q.astype(np.int8), np.float32(s_w / s_next), np.float32(b / s_next), relu))
        targets.append(z_f / s_next)
        if k < last:
            q_a = _round_clip(np.maximum(q_a @ Q * (s_w / s_next) + b / s_next, 0))
            s_a = s_next
    q = QuantNet(np.float32(in_mean), np.float32(1.0 / _scale(x - in_mean)), layers,
                 np.float32(net.out_offset))
    if REFIT:
        refit_affine(q, x, targets)
    for k, passes, rows in REFINE:
        if -len(layers) <= k < len(layers):
            refine_rounding(q, net, x, layer=k, passes=passes, rows=rows, error_scale=error_scale)
    return q


def refit_affine(q: QuantNet, x: np.ndarray, targets: list[np.ndarray], min_rows: int = 16) -> None:
    """Per output channel, the least-squares mult and bias that make acc * mult + bias match the
    float network's pre-activation (`targets[k]` (B, out_k), in layer k's output units) on the
    calibration rows x (B, in) Pa, layer by layer on the int8 network's own inputs. A ReLU layer
    fits only the rows where the float or the int8 value is positive (the ReLU cuts the others)."""
    a = _quantize_input(q, x)
    for k, L in enumerate(q.layers):
        acc = _int_matmul(a, L.q_w)
        t = targets[k]
        y = acc * L.mult + L.bias
        use = (t > 0) | (y > 0) if L.relu else np.ones(t.shape, bool)
        for o in range(acc.shape[1]):
            m = use[:, o]
            if m.sum() >= min_rows and np.ptp(acc[m, o]) > 0:
                A = np.stack([acc[m, o], np.ones(int(m.sum()))], 1)
                (L.mult[o], L.bias[o]), *_ = np.linalg.lstsq(A, t[m, o], rcond=None)
        if k < len(q.layers) - 1:
            y = np.float32(acc) * L.mult + L.bias
            a = _round_clip(np.maximum(y, np.float32(0)) if L.relu else y).astype(np.int64)


def _int_matmul(a: np.ndarray, q_w: np.ndarray) -> np.ndarray:
    """Exact integer a @ q_w through float64 BLAS (every partial sum stays far below 2^53)."""
    return a.astype(np.float64) @ q_w.astype(np.float64)


def _quantize_input(q: QuantNet, x: np.ndarray) -> np.ndarray:
    return _round_clip((np.float32(x) - q.in_mean) * q.in_inv_scale).astype(np.int64)


def _run_from(q: QuantNet, k: int, a: np.ndarray) -> np.ndarray:
    """Layers k.. of the int8 network on integer activations a (B, in_k): -> (B, out) physical."""
    return _tail(q, k, _int_matmul(a, q.layers[k].q_w))


def _inputs_of(q: QuantNet, k: int, x: np.ndarray) -> np.ndarray:
    """Integer activations entering layer k."""
    a = _quantize_input(q, x)
    for L in q.layers[:k]:
        y = np.float32(_int_matmul(a, L.q_w)) * L.mult + L.bias
        a = _round_clip(np.maximum(y, np.float32(0)) if L.relu else y).astype(np.int64)
    return a


def simulate(q: QuantNet, x: np.ndarray) -> np.ndarray:
    """The int8 network in numpy (exact integer accumulation, float32 rescale): (B, in) Pa -> (B, out)."""
    return _run_from(q, 0, _quantize_input(q, x))


def _tail(q: QuantNet, k: int, acc: np.ndarray) -> np.ndarray:
    """Layers k.. of the int8 network from layer k's int32 sums acc (B, out_k): -> (B, out) physical."""
    last = len(q.layers) - 1
    for j in range(k, last + 1):
        L = q.layers[j]
        y = np.float32(acc) * L.mult + L.bias
        if L.relu:
            y = np.maximum(y, np.float32(0))
        if j < last:
            acc = _int_matmul(_round_clip(y), q.layers[j + 1].q_w)
    return (y + q.out_offset).astype(np.float64)


class _LayerSearch:
    """Outputs of the int8 network while one weight q_w[i, o] of layer k moves: the move changes
    column o of the layer's sums by a rank-one term, the next layer's sums by another, and only the
    layers after that are recomputed (the last layer's moves change one output column)."""

    def __init__(self, q: QuantNet, k: int, x: np.ndarray):
        self.q, self.k, self.L = q, k, q.layers[k]
        self.a = _inputs_of(q, k, x).astype(np.float64)
        self.acc = _int_matmul(self.a, self.L.q_w)
        self.last = k == len(q.layers) - 1
        if self.last:
            self.y = _tail(q, k, self.acc)
        else:
            self.h = self._act(self.acc, slice(None))
            self.next = q.layers[k + 1]
            self.acc_next = _int_matmul(self.h, self.next.q_w)

    def _act(self, acc: np.ndarray, o) -> np.ndarray:
        y = np.float32(acc) * self.L.mult[o] + self.L.bias[o]
        if self.L.relu:
            y = np.maximum(y, np.float32(0))
        return y if self.last else _round_clip(y).astype(np.float64)

    def outputs(self, i: int, o: int, step: int) -> tuple[np.ndarray, tuple]:
        """(network outputs (B, out) with q_w[i, o] moved by step, the state that `accept` takes)."""
        col = self.acc[:, o] + step * self.a[:, i]
        if self.last:
            y = self.y.copy()
            y[:, o] = (self._act(col, o) + self.q.out_offset[o]).astype(np.float64)
            return y, (col, y)
        h = self._act(col, o)
        acc_next = self.acc_next + np.outer(h - self.h[:, o], self.next.q_w[o].astype(np.float64))
        return _tail(self.q, self.k + 1, acc_next), (col, h, acc_next)

    def accept(self, o: int, state: tuple) -> None:
        self.acc[:, o] = state[0]
        if self.last:
            self.y = state[1]
        else:
            self.h[:, o], self.acc_next = state[1], state[2]

    def current(self) -> np.ndarray:
        return self.y if self.last else _tail(self.q, self.k + 1, self.acc_next)


def refine_rounding(q: QuantNet, net: DeployNet, x_cal: np.ndarray, layer: int = 0, passes: int = 2,
                    rows: int = 1500, error_scale: np.ndarray | None = None) -> float:
    """Greedy adaptive rounding of one layer: move each int8 weight of `layer` by +-1 where that
    lowers the mean squared output error against the float network (in output-scale units) on
    calibration rows. The first layer, with only eight inputs per channel, is where rounding costs
    most. Returns the final loss."""
    x = np.asarray(x_cal, np.float64)
    if len(x) > rows:  # evenly spread over the calibration rows (they are in time order, run by run)
        x = x[np.unique(np.linspace(0, len(x) - 1, rows).round().astype(int))]
    target = net.forward(x)
    scale = net.out_scale if error_scale is None else np.maximum(np.asarray(error_scale, np.float64), 1e-12)
    layer = layer % len(q.layers)
    L = q.layers[layer]
    search = _LayerSearch(q, layer, x)

    def loss(y: np.ndarray) -> float:
        return float((((y - target) / scale) ** 2).mean())

    best = loss(search.current())
    for _ in range(passes):
        for i, o in np.ndindex(L.q_w.shape):
            for step in (-1, 1):
                v = int(L.q_w[i, o]) + step
                if abs(v) > W_MAX:
                    continue
                y, state = search.outputs(i, o, step)
                new = loss(y)
                if new < best:
                    best = new
                    L.q_w[i, o] = v
                    search.accept(o, state)
                    break  # the other direction undoes this move
    return best
