"""The deployed sensors' firmware struct (`shared/reference/deployed_nets.json` layout).

A firmware net holds w1[8][12], w2[12][64], w3[64][64], w4[64][5] (input-major: y = x @ w),
b1..b4, and minims/maxims[13]: indices 0..4 scale the outputs (Fx, Fy, Fz in N, theta, phi in
deg), 5..12 the eight tared pressures (Pa). Forward:
    x_i = (p_i - minims[5+i]) / (maxims[5+i] - minims[5+i])
    h = relu(x @ w1 + b1); h = relu(h @ w2 + b2); h = relu(h @ w3 + b3); o = relu(h @ w4 + b4)
    y_k = o_k * (maxims[k] - minims[k]) + minims[k]
The ReLU on the output layer means y_k >= minims[k]: a model exported to this layout gets output
minima below every value it can produce on the reference rows (checked; see `to_firmware`).

Imported nets become anytip models with an output ReLU, angles converted to rad, and the firmware's
scaling literals recorded in meta["firmware"], so that exporting them back is exact (==).
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import torch

from anytip.deploy.net import FINGERTIP_OUTPUTS, DeployNet, require_relu
from anytip.deploy.rounding import Layer, export_tolerance
from anytip.errors import AnytipError
from anytip.models.io import LoadedModels
from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.models.scaler import Scaler
from anytip.rundir import write_json

KEYS_W, KEYS_B = ("w1", "w2", "w3", "w4"), ("b1", "b2", "b3", "b4")
SIZES = (8, 12, 64, 64, 5)
N_OUT = 5
OUTPUT_NAMES = list(FINGERTIP_OUTPUTS)
ANGLE_OUTPUTS = (3, 4)  # theta, phi: deg in the firmware, rad in anytip
DEG = math.pi / 180.0
DECIMALS = 14  # the firmware tables' weights are float32 values written with 14 decimals
DESCRIPTION = (
    "MLP in the sensor firmware's C struct layout (8 barometers -> Fx, Fy, Fz [N], theta, phi [deg]). "
    "Layout: w1[in][out] (8x12), w2 (12x64), w3 (64x64), w4 (64x5); b1..b4 biases. Forward: "
    "x_i = (p_i - minims[5+i]) / (maxims[5+i] - minims[5+i]) with p_i the tared barometer reading; "
    "h = relu(x @ w1 + b1); h = relu(h @ w2 + b2); h = relu(h @ w3 + b3); o = relu(h @ w4 + b4); "
    "y_k = o_k * (maxims[k] - minims[k]) + minims[k] for k = 0..4. Written by `anytip export`.")


def read_firmware_json(path: str | Path) -> dict[str, dict[str, np.ndarray]]:
    """{unit: {key: float64 array}} from a deployed-nets JSON; bad layouts name the file and key."""
    path = Path(path)
    try:
        units = json.loads(path.read_text())["units"]
    except (OSError, json.JSONDecodeError, KeyError, TypeError) as e:
        raise AnytipError(f"{path}: not a firmware nets JSON with a 'units' object ({e})") from e
    return {name: _check_net(path, name, net) for name, net in units.items()}


def _check_net(path: Path, name: str, net: dict[str, Any]) -> dict[str, np.ndarray]:
    shapes = {**{k: (i, o) for k, i, o in zip(KEYS_W, SIZES[:-1], SIZES[1:], strict=True)},
              **{k: (o,) for k, o in zip(KEYS_B, SIZES[1:], strict=True)}, "minims": (13,), "maxims": (13,)}
    out = {}
    for key, shape in shapes.items():
        if key not in net:
            raise AnytipError(f"{path}: unit {name!r} has no key {key!r}")
        a = np.asarray(net[key], dtype=np.float64)
        if a.shape != shape:
            raise AnytipError(f"{path}: unit {name!r} key {key!r} has shape {a.shape}, expected {shape}")
        out[key] = a
    if np.any(out["maxims"] <= out["minims"]):
        raise AnytipError(f"{path}: unit {name!r} has maxims <= minims at "
                          f"{np.flatnonzero(out['maxims'] <= out['minims']).tolist()}")
    return out


def firmware_forward(net: dict[str, np.ndarray], p: np.ndarray) -> np.ndarray:
    """The firmware's forward pass in float64: p (B, 8) tared Pa -> (B, 5) in N, N, N, deg, deg."""
    lo, hi = net["minims"], net["maxims"]
    h = (np.asarray(p, np.float64) - lo[N_OUT:]) / (hi[N_OUT:] - lo[N_OUT:])
    for w, b in zip(KEYS_W, KEYS_B, strict=True):
        h = np.maximum(h @ net[w] + net[b], 0.0)
    return h * (hi[:N_OUT] - lo[:N_OUT]) + lo[:N_OUT]


def firmware_tolerance(net: dict[str, np.ndarray], p: np.ndarray) -> np.ndarray:
    """(B, 5) bound on how far the firmware's float32 forward pass (and its weights stored as
    float32) may lie from the exact one on rows p, in anytip units (angles in rad)."""
    lo, hi = net["minims"], net["maxims"]
    span_in, span_out = hi[N_OUT:] - lo[N_OUT:], (hi[:N_OUT] - lo[:N_OUT]) * _deg_factors()
    layers: list[Layer] = [(np.diag(1.0 / span_in), -lo[N_OUT:] / span_in, None)]
    layers += [(net[w], net[b], "relu") for w, b in zip(KEYS_W, KEYS_B, strict=True)]
    layers.append((np.diag(span_out), lo[:N_OUT] * _deg_factors(), None))
    return export_tolerance(layers, p)


def to_rad(y: np.ndarray) -> np.ndarray:
    """Firmware outputs (.., 5) with angles in deg -> anytip units (angles in rad)."""
    y = np.array(y, dtype=np.float64)
    y[..., list(ANGLE_OUTPUTS)] *= DEG
    return y


def _deg_factors() -> np.ndarray:
    f = np.ones(N_OUT)
    f[list(ANGLE_OUTPUTS)] = DEG
    return f


def import_firmware(nets: dict[str, dict[str, np.ndarray]]) -> LoadedModels:
    """Firmware nets -> one anytip model file's content (one model per net, output ReLU, rad)."""
    names = list(nets)
    cfg = MLPConfig(sizes=SIZES, activation="relu", output_activation="relu")
    plains = [[(torch.tensor(n[w], dtype=torch.float32), torch.tensor(n[b], dtype=torch.float32))
               for w, b in zip(KEYS_W, KEYS_B, strict=True)] for n in nets.values()]
    model = BatchedMLP.from_plain(plains, cfg)
    lo = np.stack([n["minims"] for n in nets.values()])
    hi = np.stack([n["maxims"] for n in nets.values()])
    f = _deg_factors()

    def scaler(mean: np.ndarray, std: np.ndarray) -> Scaler:
        return Scaler(torch.tensor(mean, dtype=torch.float32)[:, None],
                      torch.tensor(std, dtype=torch.float32)[:, None])

    in_s = scaler(lo[:, N_OUT:], hi[:, N_OUT:] - lo[:, N_OUT:])
    out_s = scaler(lo[:, :N_OUT] * f, (hi[:, :N_OUT] - lo[:, :N_OUT]) * f)
    meta = {"unit_ids": names, "output_names": OUTPUT_NAMES, "source": "firmware",
            "firmware": {n: {"minims": nets[n]["minims"].tolist(), "maxims": nets[n]["maxims"].tolist()}
                         for n in names}}
    return LoadedModels(model, in_s, out_s, meta)


def _recorded_scaling(loaded: LoadedModels, index: int) -> tuple[np.ndarray, np.ndarray] | None:
    """The firmware literals an imported net carries, if its scalers still equal them (float32)."""
    unit = str((loaded.meta.get("unit_ids") or [index])[index])
    rec = (loaded.meta.get("firmware") or {}).get(unit)
    if rec is None or loaded.model.config.output_activation != "relu":
        return None
    lo, hi = np.asarray(rec["minims"], np.float64), np.asarray(rec["maxims"], np.float64)
    f = _deg_factors()
    want = [lo[N_OUT:], hi[N_OUT:] - lo[N_OUT:], lo[:N_OUT] * f, (hi[:N_OUT] - lo[:N_OUT]) * f]
    have = [t[index, 0].cpu().numpy() for t in (loaded.in_scaler.mean, loaded.in_scaler.std,
                                                 loaded.out_scaler.mean, loaded.out_scaler.std)]
    same = all(np.array_equal(np.float32(w), h) for w, h in zip(want, have, strict=True))
    return (lo, hi) if same else None


def to_firmware(loaded: LoadedModels, index: int, net: DeployNet, x_ref: np.ndarray,
                margin: float = 0.1, targets: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Model `index` in the firmware layout (float64 arrays holding float32 values).

    An imported net whose scalers are unchanged is written with its own weights and scaling
    literals. Any other model keeps its input standardisation (minims = mean, maxims = mean + std)
    and gets output scalings chosen so the output ReLU clips nothing: minims[k] sits `margin`
    output ranges below the lowest of the model's outputs on `x_ref` (B, 8) (Pa) and the `targets`
    (B, 5) if given, maxims[k] as far above the highest. A model with an output ReLU of its own
    is written as is.
    """
    require_relu(net, "firmware")
    if tuple(loaded.model.config.sizes) != SIZES:
        raise AnytipError(f"the firmware struct holds an MLP of sizes {SIZES}, "
                          f"this model has {tuple(loaded.model.config.sizes)}")
    rec = _recorded_scaling(loaded, index)
    plain = [(W.double().cpu().numpy(), b.double().cpu().numpy()) for W, b in loaded.model.to_plain(index)]
    if rec is not None:
        lo, hi = rec
    else:
        lo, hi, plain = _fold_scaling(loaded, index, net, plain, x_ref, margin, targets)
    out = {k: _f32(W) for k, (W, _) in zip(KEYS_W, plain, strict=True)}
    out |= {k: _f32(b) for k, (_, b) in zip(KEYS_B, plain, strict=True)}
    return out | {"minims": lo, "maxims": hi}


def _fold_scaling(loaded: LoadedModels, index: int, net: DeployNet, plain: list, x_ref: np.ndarray,
                  margin: float, targets: np.ndarray | None) -> tuple[np.ndarray, np.ndarray, list]:
    """Firmware min/max literals for a general model, its scalers folded into the outer layers."""
    m_in, s_in = net.in_mean, net.in_std
    s_out = loaded.out_scaler.std[index, 0].double().cpu().numpy()
    m_out = loaded.out_scaler.mean[index, 0].double().cpu().numpy()
    f = _deg_factors()
    own_relu = loaded.model.config.output_activation == "relu"
    if own_relu:
        lo_out, hi_out = m_out, m_out + s_out
    else:
        y = net.forward(x_ref)
        y = y if targets is None else np.concatenate([y, np.asarray(targets, np.float64)])
        span = np.maximum(y.max(0) - y.min(0), s_out)
        lo_out, hi_out = y.min(0) - margin * span, y.max(0) + margin * span
    lo = np.concatenate([_round_lit(lo_out / f), _round_lit(m_in)])
    hi = np.concatenate([_round_lit(hi_out / f), _round_lit(m_in + s_in)])
    # firmware x = (p - lo) / r; the model wants (p - m) / s = x * r / s + (lo - m) / s
    W0, b0 = plain[0]
    r_in = hi[N_OUT:] - lo[N_OUT:]
    plain[0] = (W0 * (r_in / s_in)[:, None], b0 + ((lo[N_OUT:] - m_in) / s_in) @ W0)
    if not own_relu:
        # the firmware's pre-ReLU output o = (z * s + m - lo) / r, with z the model's last layer
        W, b = plain[-1]
        lo_o, r_o = lo[:N_OUT] * f, (hi[:N_OUT] - lo[:N_OUT]) * f
        plain[-1] = (W * (s_out / r_o), (b * s_out + m_out - lo_o) / r_o)
    return lo, hi, plain


def _round_lit(a: np.ndarray) -> np.ndarray:
    """Scaling literals as float32 values (what a float struct holds)."""
    return np.float32(a).astype(np.float64)


def _f32(a: np.ndarray) -> np.ndarray:
    """float32 values rounded to the tables' 14 decimals (exact for float32 weights of size < 1e3)."""
    flat = [float(f"{v:.{DECIMALS}f}") for v in np.float32(a).astype(np.float64).ravel()]
    return np.array(flat, dtype=np.float64).reshape(np.shape(a))


def clipped_outputs(net_fw: dict[str, np.ndarray], x_ref: np.ndarray) -> int:
    """How many pre-ReLU outputs on x_ref (B, 8) Pa are negative (the firmware would clip them)."""
    lo, hi = net_fw["minims"], net_fw["maxims"]
    h = (np.asarray(x_ref, np.float64) - lo[N_OUT:]) / (hi[N_OUT:] - lo[N_OUT:])
    for w, b in zip(KEYS_W[:-1], KEYS_B[:-1], strict=True):
        h = np.maximum(h @ net_fw[w] + net_fw[b], 0.0)
    return int(np.sum(h @ net_fw["w4"] + net_fw["b4"] < 0))


def write_firmware_json(path: str | Path, nets: dict[str, dict[str, np.ndarray]], description: str) -> Path:
    """Write nets in the deployed-nets JSON layout (key order w1..w4, b1..b4, minims, maxims)."""
    order = (*KEYS_B, *KEYS_W, "minims", "maxims")
    doc = {"description": description,
           "units": {n: {k: net[k].tolist() for k in order} for n, net in nets.items()}}
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_json(path, doc, indent=None)
    return path


def write_firmware_c(path: str | Path, net: dict[str, np.ndarray], unit: str) -> Path:
    """The same tables as C initialisers (float w1[8][12], ..., minims[13], maxims[13])."""
    from anytip.deploy.c_export import c_floats

    lines = [f"/* anytip contact model, unit {unit}, in the firmware's struct layout. "
             "Generated by `anytip export`. */"]
    for k in (*KEYS_W, *KEYS_B, "minims", "maxims"):
        dims = "".join(f"[{d}]" for d in net[k].shape)
        lines.append(f"static const float {k}{dims} = {{\n{c_floats(net[k].ravel())}\n}};")
    path = Path(path)
    path.write_text("\n".join(lines) + "\n")
    return path
