"""ONNX export: one self-contained file (weights inline), opset 18, dynamic batch.

Input `pressure` (batch, 8) float32 tared Pa; output `contact` (batch, 5) float32 in N and rad.
The scalers are folded into the graph's first and last layers (see `anytip.deploy.net`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

from anytip.deploy.net import LEAKY_SLOPE, DeployNet
from anytip.errors import AnytipError

OPSET = 18
IR_VERSION = 9  # readable by every onnxruntime that runs opset 18
INPUT, OUTPUT = "pressure", "contact"


def _activation_node(activation: str, x: str, y: str, k: int) -> onnx.NodeProto:
    """Relu, LeakyRelu (alpha 0.01) or HardSwish (opset 14+; x * clip(x + 3, 0, 6) / 6)."""
    if activation == "relu":
        return helper.make_node("Relu", [x], [y], name=f"relu{k}")
    if activation == "leaky_relu":
        return helper.make_node("LeakyRelu", [x], [y], name=f"leaky_relu{k}", alpha=LEAKY_SLOPE)
    if activation == "hardswish":
        return helper.make_node("HardSwish", [x], [y], name=f"hardswish{k}")
    raise AnytipError(f"activation {activation!r} has no ONNX export")


def build_onnx(net: DeployNet) -> onnx.ModelProto:
    """The network as an ONNX graph: Gemm layers (float32), the hidden activation between, output
    offset."""
    nodes, inits = [], []
    h = INPUT
    last = len(net.layers) - 1
    for k, (W, b) in enumerate(net.layers):
        inits += [numpy_helper.from_array(W.astype(np.float32), f"W{k}"),
                  numpy_helper.from_array(b.astype(np.float32), f"b{k}")]
        out = f"z{k}"
        nodes.append(helper.make_node("Gemm", [h, f"W{k}", f"b{k}"], [out], name=f"dense{k}"))
        if k < last or net.output_relu:
            nodes.append(_activation_node(net.activation if k < last else "relu", out, f"h{k}", k))
            out = f"h{k}"
        h = out
    if net.output_relu:
        inits.append(numpy_helper.from_array(net.out_offset.astype(np.float32), "out_offset"))
        nodes.append(helper.make_node("Add", [h, "out_offset"], [OUTPUT], name="offset"))
    else:
        nodes.append(helper.make_node("Identity", [h], [OUTPUT], name="output"))
    graph = helper.make_graph(
        nodes, "anytip_contact",
        [helper.make_tensor_value_info(INPUT, TensorProto.FLOAT, ["batch", net.n_inputs])],
        [helper.make_tensor_value_info(OUTPUT, TensorProto.FLOAT, ["batch", net.n_outputs])],
        inits)
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", OPSET)],
                              producer_name="anytip", ir_version=IR_VERSION)
    model.doc_string = (f"anytip contact model, unit {net.unit}: tared pressures (Pa) -> "
                        f"{', '.join(net.output_names) or 'outputs'} (in the sensor model's target units)")
    onnx.checker.check_model(model, full_check=True)
    return model


def write_onnx(net: DeployNet, out_dir: str | Path, name: str = "anytip") -> Path:
    """Write `<out_dir>/<name>.onnx` (no external data)."""
    path = Path(out_dir) / f"{name}.onnx"
    path.parent.mkdir(parents=True, exist_ok=True)
    onnx.save_model(build_onnx(net), str(path), save_as_external_data=False)
    return path


def float32_parameters(net: DeployNet) -> np.ndarray:
    """The initializers `build_onnx` writes, flattened in graph order (W0, b0, W1, ..., out_offset)."""
    parts = [a for W, b in net.layers for a in (W.ravel(), b)]
    if net.output_relu:
        parts.append(net.out_offset)
    return np.concatenate(parts).astype(np.float32)


def onnx_parameters(path: str | Path) -> np.ndarray:
    """The initializers of an exported file, flattened in graph order."""
    model = onnx.load(str(path), load_external_data=False)
    return np.concatenate([numpy_helper.to_array(t).ravel() for t in model.graph.initializer]
                          ).astype(np.float32)


def run_onnx(path: str | Path, x: np.ndarray) -> np.ndarray:
    """Evaluate an exported file with onnxruntime (CPU): x (B, 8) Pa -> (B, 5)."""
    import onnxruntime as ort

    opts = ort.SessionOptions()
    opts.intra_op_num_threads = opts.inter_op_num_threads = 1
    sess = ort.InferenceSession(str(path), opts, providers=["CPUExecutionProvider"])
    return sess.run([OUTPUT], {INPUT: np.asarray(x, np.float32)})[0].astype(np.float64)
