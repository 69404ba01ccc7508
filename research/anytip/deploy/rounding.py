"""How far an exported float32 network may lie from the float64 reference: a rounding error bound.

Forward error analysis of one layer a = W^T h + b evaluated in precision u (unit roundoff;
2^-24 for float32) with n = fan-in + 1 terms, in any summation order and with or without fused
multiply-adds (Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., eq. 3.5):

    |a_computed - a| <= |W_r - W|^T |h_r| + |W|^T |dh| + |b_r - b| + gamma_n (|W_r|^T |h_r| + |b_r|)

with W_r, b_r the parameters rounded to the precision, h_r = h + dh the layer's computed input
(|h_r| <= |h| + |dh|) and gamma_n = n u / (1 - n u). Activations pass the error on scaled by
their Lipschitz constant (1 for ReLU and leaky ReLU, 1.5 for hardswish) plus their own rounding.
The bound is evaluated row by row on the rows an export is verified on, so it follows what those
rows actually exercise: cancellation in a sum widens it as it widens the error. It is a guarantee,
not an estimate (measured errors reach 0.1-2% of it), so a small change of one weight can hide
inside it; export verification therefore also compares the exported parameters bit for bit.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from anytip.deploy.net import DeployNet, activate

U_FLOAT32 = 2.0**-24
U_FLOAT64 = 2.0**-53
LIPSCHITZ = {None: 1.0, "relu": 1.0, "leaky_relu": 1.0, "hardswish": 1.5}

Layer = tuple[np.ndarray, np.ndarray, str | None]  # W (in, out), b (out,), activation after it


def gamma(n: int, u: float) -> float:
    """gamma_n = n u / (1 - n u): the relative error bound of an n-term sum or dot product."""
    if n * u >= 1:
        raise ValueError(f"gamma_{n} undefined at u={u}")
    return n * u / (1 - n * u)


def _round(a: np.ndarray, u: float) -> np.ndarray:
    """`a` rounded to the precision of u (float32 for U_FLOAT32; float64 left as it is)."""
    return a.astype(np.float32).astype(np.float64) if u >= U_FLOAT32 else a


def _activation_rounding(a: np.ndarray, act: str | None, u: float) -> np.ndarray:
    """Rounding the activation itself adds: none for ReLU; a product for leaky ReLU; a few
    operations on |a| (|a| + 3) / 6 for hardswish."""
    if act == "leaky_relu":
        return 2 * u * 0.01 * np.abs(a)
    if act == "hardswish":
        return 5 * u * np.abs(a) * (np.abs(a) + 3) / 6
    return np.zeros_like(a)


def error_bound(layers: Sequence[Layer], x: np.ndarray, u: float = U_FLOAT32,
                out_offset: np.ndarray | None = None) -> np.ndarray:
    """(B, out) bound on |network(x) computed in precision u - network(x) in exact arithmetic|.

    `layers` in float64, each followed by its activation; `x` (B, in) the inputs as the export
    receives them (their own rounding to the precision is included); `out_offset` a vector
    added last (one more rounding).
    """
    h = np.asarray(x, np.float64)
    e = np.abs(_round(h, u) - h)
    for W, b, act in layers:
        W_r, b_r = _round(W, u), _round(b, u)
        h_r = np.abs(h) + e
        n = W.shape[0] + 1
        err = (h_r @ np.abs(W_r - W) + e @ np.abs(W) + np.abs(b_r - b)
               + gamma(n, u) * (h_r @ np.abs(W_r) + np.abs(b_r)))
        a = h @ W + b
        e = LIPSCHITZ[act] * err + _activation_rounding(np.abs(a) + err, act, u)
        h = a if act is None else activate(a, act)
    if out_offset is not None and np.any(out_offset):
        off = np.asarray(out_offset, np.float64)
        y = h + off
        e = e + np.abs(_round(off, u) - off) + u * (np.abs(y) + e)
    return e


def export_tolerance(layers: Sequence[Layer], x: np.ndarray, out_offset: np.ndarray | None = None,
                     u: float = U_FLOAT32) -> np.ndarray:
    """(B, out) tolerance of an export computed in precision u against the float64 reference:
    its rounding bound plus the float64 reference's own (folding and evaluating in float64)."""
    return (error_bound(layers, x, u, out_offset)
            + 4 * error_bound(layers, x, U_FLOAT64, out_offset))


def check(y: np.ndarray, ref: np.ndarray, tolerance: np.ndarray, scale: np.ndarray) -> dict:
    """Verification of outputs y (B, out) against ref within `tolerance` (B, out) element by
    element: the largest error, the largest bound, their largest ratio (<= 1 passes), and the
    largest error relative to each output's scale (for comparison across models)."""
    d = np.abs(np.asarray(y, np.float64) - ref)
    ratio = d / np.maximum(tolerance, np.finfo(np.float64).tiny)
    return {"max_abs_err": d.max(0).tolist(), "max_bound": tolerance.max(0).tolist(),
            "max_err_over_bound": float(ratio.max()), "max_rel_err": float((d.max(0) / scale).max()),
            "passed": bool((d <= tolerance).all())}


def network_layers(net: DeployNet) -> list[Layer]:
    """A DeployNet's layers with the activation after each, as `error_bound` takes them."""
    last = len(net.layers) - 1
    return [(W, b, net.activation if k < last else ("relu" if net.output_relu else None))
            for k, (W, b) in enumerate(net.layers)]


def network_tolerance(net: DeployNet, x: np.ndarray, u: float = U_FLOAT32) -> np.ndarray:
    """(B, out) how far `net` computed in precision u (float32 by default) may lie from the
    float64 reference on rows x: `export_tolerance` of its layers."""
    return export_tolerance(network_layers(net), x, net.out_offset, u)
