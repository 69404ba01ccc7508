"""The same unit exported by other tools, for side-by-side measures (experiments/deploy.yaml).

- emlearn (`emlearn.convert` of a scikit-learn MLPRegressor holding the unit's standardised-space
  weights, 'loadable' C); the input and output scalings run in a small wrapper.
- emx-onnx-cgen (ONNX to C) on anytip's own ONNX export, batch pinned to 1, temporaries on the stack.
Each peer gets the wrapper `void anytip_infer(const float *in, float *out)`, so the measures of
`anytip.deploy.embedded` and `anytip.deploy.native` apply unchanged.
"""

from __future__ import annotations

import contextlib
import shutil
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

from anytip.deploy.c_export import c_floats
from anytip.deploy.net import DeployNet
from anytip.deploy.onnx_export import INPUT, write_onnx
from anytip.errors import AnytipError
from anytip.models.io import LoadedModels


def _import_emlearn():
    """emlearn, imported without its side effect: it sets numpy to raise on every floating-point
    warning (underflow included) for the whole process."""
    saved = np.geterr()
    try:
        import emlearn
    finally:
        np.seterr(**saved)
    return emlearn


def peer_missing(name: str) -> str | None:
    """Why a peer cannot run here, or None."""
    if name == "emlearn":
        try:
            _import_emlearn()
        except ImportError:
            return "emlearn is not installed (pip install emlearn; it is in the dev extras)"
        return None
    if name == "emx-onnx-cgen":
        if _emx() is None:
            return "emx-onnx-cgen is not installed (pip install emx-onnx-cgen; it is in the dev extras)"
        return None
    raise AnytipError(f"unknown peer {name!r} (known: emlearn, emx-onnx-cgen)")


def _emx() -> str | None:
    exe = Path(sys.executable).with_name("emx-onnx-cgen")
    return str(exe) if exe.exists() else shutil.which("emx-onnx-cgen")


def _standardised(loaded: LoadedModels, index: int) -> list[tuple[np.ndarray, np.ndarray]]:
    return [(W.double().cpu().numpy(), b.double().cpu().numpy()) for W, b in loaded.model.to_plain(index)]


def write_emlearn(loaded: LoadedModels, index: int, net: DeployNet,
                  out_dir: str | Path) -> tuple[Path, tuple]:
    """emlearn's C for the unit plus the wrapper; returns (source, include dirs)."""
    emlearn = _import_emlearn()
    from sklearn.neural_network import MLPRegressor

    if loaded.model.config.output_activation is not None or net.activation != "relu":
        raise AnytipError("the emlearn peer takes ReLU models without an output activation "
                          f"(this one: {net.activation!r}, output {loaded.model.config.output_activation!r})")
    plain = _standardised(loaded, index)
    sizes = [plain[0][0].shape[0]] + [W.shape[1] for W, _ in plain]
    reg = MLPRegressor(hidden_layer_sizes=tuple(sizes[1:-1]), activation="relu", max_iter=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        reg.fit(np.zeros((2, sizes[0])), np.zeros((2, sizes[-1])))  # sets the shapes
    reg.coefs_ = [W.astype(np.float32) for W, _ in plain]
    reg.intercepts_ = [b.astype(np.float32) for _, b in plain]
    out_dir = Path(out_dir).resolve()  # absolute before the chdir below
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp, contextlib.chdir(tmp):  # emlearn builds a test binary in ./tmp
        emlearn.convert(reg, method="loadable", return_type="regressor").save(
            file=str(out_dir / "peer_emlearn.h"), name="peer_emlearn")
    m_in, s_in = net.in_mean, net.in_std
    s_out = loaded.out_scaler.std[index, 0].double().numpy()
    m_out = loaded.out_scaler.mean[index, 0].double().numpy()
    src = out_dir / "peer_emlearn.c"
    src.write_text(f"""#include "peer_emlearn.h"
static const float IN_MEAN[{net.n_inputs}] = {{\n{c_floats(m_in)}\n}};
static const float IN_INV_STD[{net.n_inputs}] = {{\n{c_floats(1.0 / s_in)}\n}};
static const float OUT_MEAN[{net.n_outputs}] = {{\n{c_floats(m_out)}\n}};
static const float OUT_STD[{net.n_outputs}] = {{\n{c_floats(s_out)}\n}};
void anytip_infer(const float *in, float *out)
{{
    float z[{net.n_inputs}];
    for (int i = 0; i < {net.n_inputs}; i++) z[i] = (in[i] - IN_MEAN[i]) * IN_INV_STD[i];
    peer_emlearn_regress(z, {net.n_inputs}, out, {net.n_outputs});
    for (int k = 0; k < {net.n_outputs}; k++) out[k] = out[k] * OUT_STD[k] + OUT_MEAN[k];
}}
""")
    return src, (str(Path(emlearn.includedir)),)


def write_emx(net: DeployNet, out_dir: str | Path) -> tuple[Path, tuple]:
    """emx-onnx-cgen's C for anytip's ONNX export plus the wrapper; returns (source, include dirs)."""
    out_dir = Path(out_dir)
    onnx_path = write_onnx(net, out_dir, "peer_emx")
    gen = out_dir / "peer_emx_gen.c"
    cmd = [_emx() or "emx-onnx-cgen", "compile", str(onnx_path), str(gen), "--color", "never",
           "--model-name", "peer_emx", "--input-dim", f"{INPUT}:0=1", "--large-temp-threshold", "0"]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        raise AnytipError(f"emx-onnx-cgen failed on {onnx_path}:\n{res.stderr.strip() or res.stdout.strip()}")
    src = out_dir / "peer_emx.c"
    src.write_text(f"""#include "peer_emx_gen.c"
void anytip_infer(const float *in, float *out)
{{
    peer_emx((const float (*)[{net.n_inputs}])in, (float (*)[{net.n_outputs}])out);
}}
""")
    return src, ()


PEERS = ("emlearn", "emx-onnx-cgen")


def measure_peer(name: str, loaded: LoadedModels, index: int, net: DeployNet, ref, y_model: np.ndarray,
                 out_dir: str | Path) -> dict:
    """Write peer `name`'s C for the unit and measure it like anytip's C export (see export.measure)."""
    from anytip.deploy.export import errors, measure, scores
    from anytip.deploy.native import run_c

    why = peer_missing(name)
    if why:
        return {"peer": name, "skipped": why}
    out_dir = Path(out_dir)
    src, inc = write_emlearn(loaded, index, net, out_dir) if name == "emlearn" else write_emx(net, out_dir)
    y = run_c(src, ref.x, net.n_outputs, includes=inc, strict=False)
    return {"peer": name, "files": sorted(p.name for p in out_dir.iterdir() if p.is_file()),
            "gcc_host": errors(y, y_model, net, ref.x), "scores": scores(y, ref),
            "cortex_m4": measure(src, net, ref.x, y, out_dir / "build", inc, strict=False)}
