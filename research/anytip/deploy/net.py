"""One unit of a saved model as plain float64 arrays, with its scalers folded into the layers.

A `DeployNet` computes, for tared pressures x (B, C) in Pa:
    h = x @ W[0] + b[0];  h = act(h) between layers;  h = relu(h) after the last layer if
    `output_relu`;  y = h + out_offset
where act is `activation`: relu, leaky_relu (negative slope 0.01) or hardswish
(x * clamp(x + 3, 0, 6) / 6), as torch defines them.
with y (B, D) in the physical units of the targets it was trained on (the fingertip's, FINGERTIP_OUTPUTS:
N, rad). The input standardisation is folded into W[0], b[0] and the output scale into W[-1], b[-1];
`out_offset` is the output mean when an output ReLU keeps it from being folded (it is zero otherwise).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import torch

from anytip.errors import AnytipError
from anytip.models.io import LoadedModels, load_models

ACTIVATIONS = ("relu", "leaky_relu", "hardswish")
FINGERTIP_OUTPUTS = ("fx", "fy", "fz", "theta", "phi")  # the fingertip's outputs: N, N, N, rad, rad
LEAKY_SLOPE = 0.01  # torch's default negative slope


def activate(h: np.ndarray, activation: str) -> np.ndarray:
    """A hidden activation of ACTIVATIONS, elementwise, in h's dtype."""
    if activation == "relu":
        return np.maximum(h, 0)
    if activation == "leaky_relu":
        return np.where(h > 0, h, h * h.dtype.type(LEAKY_SLOPE))
    if activation == "hardswish":
        return h * np.clip(h + 3, 0, 6) / 6
    raise AnytipError(f"activation {activation!r} does not export (exportable: {', '.join(ACTIVATIONS)})")


def require_relu(net: DeployNet, fmt: str) -> None:
    """Formats whose arithmetic assumes ReLU (int8 requantisation, the firmware struct) refuse others."""
    if net.activation != "relu":
        raise AnytipError(f"unit {net.unit}: --format {fmt} supports ReLU networks only; this model's "
                          f"hidden activation is {net.activation!r} (export it as onnx or c)")


@dataclass
class DeployNet:
    """layers [(W (in, out), b (out,)), ...] float64; out_offset (out,); see the module docstring."""

    layers: list[tuple[np.ndarray, np.ndarray]]
    output_relu: bool
    out_offset: np.ndarray
    out_scale: np.ndarray  # (out,) the model's output std in physical units: the error yardstick
    in_mean: np.ndarray  # (in,) Pa
    in_std: np.ndarray  # (in,) Pa
    output_names: list[str] = field(default_factory=list)
    unit: str = ""
    activation: str = "relu"  # hidden layers' activation, one of ACTIVATIONS

    @property
    def n_inputs(self) -> int:
        return int(self.layers[0][0].shape[0])

    @property
    def n_outputs(self) -> int:
        return int(self.layers[-1][0].shape[1])

    @property
    def macs(self) -> int:
        """Multiply-accumulates of one inference."""
        return int(sum(W.size for W, _ in self.layers))

    @property
    def n_params(self) -> int:
        return int(sum(W.size + b.size for W, b in self.layers))

    def forward(self, x: np.ndarray, dtype: type = np.float64) -> np.ndarray:
        """x (B, in) Pa -> (B, out) physical units, computed in `dtype`."""
        h = np.asarray(x, dtype=dtype)
        for k, (W, b) in enumerate(self.layers):
            h = h @ W.astype(dtype) + b.astype(dtype)
            if k < len(self.layers) - 1:
                h = activate(h, self.activation)
            elif self.output_relu:
                h = np.maximum(h, 0)
        return h + self.out_offset.astype(dtype)


def unit_index(loaded: LoadedModels, unit: str | None, path: str | Path = "model") -> int:
    """Index of `unit` in the model file (the first one if None); unknown units name the file."""
    ids = [str(u) for u in loaded.meta.get("unit_ids") or range(loaded.model.n_models)]
    if unit is None:
        return 0
    if unit not in ids:
        raise AnytipError(f"{path}: unit {unit!r} is not in the model file (units: {sorted(set(ids))})")
    return ids.index(unit)


def deploy_net(loaded: LoadedModels, index: int = 0, path: str | Path = "model") -> DeployNet:
    """Fold model `index`'s scalers into its layers (float64). Hidden activations of ACTIVATIONS,
    output activation none or ReLU."""
    cfg = loaded.model.config
    if cfg.activation not in ACTIVATIONS or cfg.output_activation not in (None, "relu"):
        raise AnytipError(f"{path}: only {', '.join(ACTIVATIONS)} hidden activations and no or a ReLU "
                          f"output activation export (activation {cfg.activation!r}, "
                          f"output_activation {cfg.output_activation!r})")
    layers = [(W.double().cpu().numpy(), b.double().cpu().numpy()) for W, b in loaded.model.to_plain(index)]
    m_in, s_in = (t[index, 0].double().cpu().numpy() for t in (loaded.in_scaler.mean, loaded.in_scaler.std))
    m_out, s_out = (t[index, 0].double().cpu().numpy()
                    for t in (loaded.out_scaler.mean, loaded.out_scaler.std))
    W0, b0 = layers[0]
    layers[0] = (W0 / s_in[:, None], b0 - (m_in / s_in) @ W0)
    if cfg.output_activation == "relu" and np.any(s_out <= 0):
        raise AnytipError(f"{path}: an output ReLU needs positive output scales, got {s_out.tolist()}")
    Wl, bl = layers[-1]
    relu_out = cfg.output_activation == "relu"
    layers[-1] = (Wl * s_out, bl * s_out + (0.0 if relu_out else m_out))
    ids = [str(u) for u in loaded.meta.get("unit_ids") or range(loaded.model.n_models)]
    return DeployNet(layers, relu_out, m_out if relu_out else np.zeros_like(m_out), s_out, m_in, s_in,
                     list(loaded.meta.get("output_names") or []), ids[index], cfg.activation)


def load_deploy_net(path: str | Path, unit: str | None = None) -> tuple[DeployNet, LoadedModels, int]:
    """Read a per-unit model file and fold one unit: (net, loaded models, unit index)."""
    loaded = load_models(path)
    i = unit_index(loaded, unit, path)
    return deploy_net(loaded, i, path), loaded, i


@torch.no_grad()
def model_predict(loaded: LoadedModels, index: int, x: np.ndarray, double: bool = True) -> np.ndarray:
    """The trained model itself (torch; its float32 parameters evaluated in float64 by default, the
    reference every export is held to): x (B, in) Pa -> (B, out) physical units."""
    dt = torch.float64 if double else torch.float32
    xt = torch.as_tensor(np.asarray(x)).to(dt)[None]
    ins, outs = loaded.in_scaler.slice(index), loaded.out_scaler.slice(index)
    ins, outs = (type(s)(s.mean.to(dt), s.std.to(dt)) for s in (ins, outs))
    z = loaded.model.model_slice(index).to(dt)(ins.transform(xt))
    return outs.inverse(z)[0].double().numpy()
