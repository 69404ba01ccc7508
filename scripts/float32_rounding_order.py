"""Max error of float32 inference against the trained model under three ways of summing.

emx-onnx-cgen's Gemm starts each sum at 0 and adds the bias last; anytip's float32 C ("bias first")
starts at the bias and adds x[i] * w[i][o] in input order; "centred" sums bias first on centred
inputs (x - c, c the input mean, with c @ W0 moved into the first bias), an alternative that
costs 68 B of flash. All use the same folded float32 weights (anytip's ONNX export). This script
evaluates the three in numpy, sequentially in float32, with separate multiply and add (what gcc
on x86-64 compiles the C to) and with a fused multiply-add (what the Cortex-M4F runs with
-ffp-contract=fast: the float32 product is exact in float64, then one rounding to float32), and
checks the unfused host figures against the compiled C of both tools.

    .venv/bin/python scripts/float32_rounding_order.py --registry data/fleet24 \
        reports/cross_sensor/models/per_unit_seed2/model.safetensors:SIM7-022

Prints, per unit, max |error| / output scale over the unit's held-out reference rows.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from anytip.data.registry import Registry
from anytip.deploy.c_export import write_c
from anytip.deploy.export import prepare
from anytip.deploy.native import run_c
from anytip.deploy.net import DeployNet
from anytip.deploy.peers import peer_missing, write_emx


def dense32(x: np.ndarray, W: np.ndarray, b: np.ndarray, bias_first: bool, fused: bool) -> np.ndarray:
    """x (B, in) @ W (in, out) + b, summed input by input in float32."""
    W32, b32, x32 = W.astype(np.float32), b.astype(np.float32), x.astype(np.float32)
    acc = np.tile(b32, (len(x), 1)) if bias_first else np.zeros((len(x), len(b)), np.float32)
    for i in range(W.shape[0]):
        if fused:
            acc = (acc.astype(np.float64) + x32[:, i:i + 1].astype(np.float64) * W32[i]).astype(np.float32)
        else:
            acc = acc + x32[:, i:i + 1] * W32[i]
    return acc if bias_first else acc + b32


def centred_layers(net: DeployNet) -> tuple[np.ndarray, list[tuple[np.ndarray, np.ndarray]]]:
    """(c, layers): c the input mean rounded to float32 (in,) Pa, the first layer taking x - c."""
    c = net.in_mean.astype(np.float32).astype(np.float64)
    (W0, b0), rest = net.layers[0], net.layers[1:]
    return c, [(W0, b0 + c @ W0), *rest]


def forward32(net: DeployNet, x: np.ndarray, bias_first: bool, fused: bool,
              centred: bool = False) -> np.ndarray:
    """The folded ReLU network (no output ReLU) in float32: (B, in) Pa -> (B, out)."""
    layers = net.layers
    h = x.astype(np.float32)
    if centred:
        c, layers = centred_layers(net)
        h = h - c.astype(np.float32)
    for k, (W, b) in enumerate(layers):
        h = dense32(h, W, b, bias_first, fused)
        if k < len(layers) - 1:
            h = np.maximum(h, 0)
    return h.astype(np.float64) + net.out_offset


def rel_err(y: np.ndarray, ref: np.ndarray, scale: np.ndarray) -> float:
    """max |y - ref| / output scale over rows and outputs."""
    return float((np.abs(y - ref).max(0) / scale).max())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("models", nargs="+", help="MODEL:UNIT (a per-unit model file and one of its units)")
    ap.add_argument("--registry", required=True)
    ap.add_argument("--rows", type=int, default=4000)
    ap.add_argument("--work", default="/tmp/anytip_rounding_order", help="where the C is compiled")
    args = ap.parse_args()
    reg = Registry(Path(args.registry), create=False)
    print(f"{'unit':<10}{'first':>10}{'last':>10}{'centred':>10}{'f.first':>10}{'f.last':>10}"
          f"{'f.centred':>10}{'anytip C':>10}{'emx C':>10}   rows")
    for spec in args.models:
        model, unit = spec.rsplit(":", 1)
        p = prepare(model, unit, reg, args.rows)
        x, net = p.ref.x, p.net
        orders = ((True, False), (False, False), (True, True))  # (bias first, centred)
        sims = [rel_err(forward32(net, x, first, fused, centred), p.y_model, net.out_scale)
                for fused in (False, True) for first, centred in orders]
        _, c = write_c(net, Path(args.work) / unit / "c")
        compiled = [rel_err(run_c(c, x, net.n_outputs), p.y_model, net.out_scale)]
        if peer_missing("emx-onnx-cgen") is None:
            src, inc = write_emx(net, Path(args.work) / unit / "emx")
            y = run_c(src, x, net.n_outputs, includes=inc, strict=False)
            compiled.append(rel_err(y, p.y_model, net.out_scale))
        cells = "".join(f"{v:>10.2e}" for v in sims + compiled)
        print(f"{unit:<10}{cells}   {p.ref.source}")


if __name__ == "__main__":
    main()
