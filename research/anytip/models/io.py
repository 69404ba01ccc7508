"""Save and load a fleet of MLPs, shared models and response models: `<name>.safetensors`
(tensors) + `<name>.json` (metadata).

No pickles anywhere: tensors go through safetensors, everything else is JSON. The JSON
holds the format version, the MLPConfig, the number of models and a free `meta` dict
(unit ids, output names, recipe, seed, ...).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import torch
from safetensors import SafetensorError, safe_open
from safetensors.torch import load_file, save, save_file
from torch import Tensor

from anytip.errors import AnytipError
from anytip.models.adapted import AdaptedMLP
from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.models.response import ResponseConfig, ResponseModel
from anytip.models.scaler import Scaler
from anytip.rundir import write_bytes, write_json

FORMAT = "anytip.batched_mlp"
FORMAT_VERSION = 1
DEFAULT_NAME = "model"


class ModelFileError(AnytipError):
    """A model file that is missing, unreadable or does not match its metadata."""

    def __init__(self, path: str | Path, problem: str):
        self.path, self.problem = str(path), problem
        super().__init__(f"{path}: {problem}")


@dataclass
class LoadedModels:
    """What `load_models` returns: the model, its scalers and the saved metadata."""

    model: BatchedMLP
    in_scaler: Scaler
    out_scaler: Scaler
    meta: dict[str, Any] = field(default_factory=dict)


def model_paths(path: str | Path) -> tuple[Path, Path]:
    """(tensors, metadata) paths: `x.safetensors` names a file; anything else is a directory."""
    path = Path(path)
    if path.suffix == ".safetensors":
        return path, path.with_suffix(".json")
    return path / f"{DEFAULT_NAME}.safetensors", path / f"{DEFAULT_NAME}.json"


def save_models(path: str | Path, model: BatchedMLP, in_scaler: Scaler, out_scaler: Scaler,
                meta: dict[str, Any] | None = None) -> Path:
    """Write the model and scalers; returns the .safetensors path. `meta` must be JSON-able."""
    meta = dict(meta or {})
    ids = meta.get("unit_ids")
    if ids is not None and len(ids) != model.n_models:
        raise ValueError(f"meta has {len(ids)} unit_ids for {model.n_models} models")
    tensors_path, json_path = model_paths(path)
    tensors_path.parent.mkdir(parents=True, exist_ok=True)
    save_file(_tensors(model, in_scaler, out_scaler), str(tensors_path))
    header = {"format": FORMAT, "format_version": FORMAT_VERSION,
              "config": model.config.model_dump(mode="json"), "n_models": model.n_models,
              "meta": meta}
    write_json(json_path, header)
    return tensors_path


def load_models(path: str | Path, device: torch.device | str = "cpu") -> LoadedModels:
    """Read what `save_models` wrote; any mismatch raises ModelFileError naming the file."""
    tensors_path, json_path = model_paths(path)
    header = read_header(json_path)
    try:
        config = MLPConfig(**header["config"])
        n_models = int(header["n_models"])
    except Exception as e:  # noqa: BLE001 - any bad header is reported the same way
        raise ModelFileError(json_path, f"bad config or n_models: {e}") from e
    tensors = _read_tensors(tensors_path, device)
    _check(tensors_path, tensors, _expected_shapes(config, n_models))
    model = BatchedMLP(n_models, config, seed=[0] * n_models).to(device)
    model.load_state_dict({k: tensors[k] for k in model.state_dict()})
    in_scaler = Scaler(tensors["in_scaler.mean"], tensors["in_scaler.std"])
    out_scaler = Scaler(tensors["out_scaler.mean"], tensors["out_scaler.std"])
    return LoadedModels(model, in_scaler, out_scaler, header.get("meta", {}))


def _tensors(model: BatchedMLP, in_scaler: Scaler, out_scaler: Scaler) -> dict[str, Tensor]:
    out = {k: v.detach().contiguous().cpu() for k, v in model.state_dict().items()}
    for name, s in (("in_scaler", in_scaler), ("out_scaler", out_scaler)):
        out[f"{name}.mean"] = s.mean.detach().contiguous().cpu()
        out[f"{name}.std"] = s.std.detach().contiguous().cpu()
    return out


def _expected_shapes(config: MLPConfig, n: int) -> dict[str, tuple[int, ...]]:
    shapes: dict[str, tuple[int, ...]] = {}
    pairs = zip(config.sizes[:-1], config.sizes[1:], strict=True)
    for k, (i, o) in enumerate(pairs):
        shapes[f"weights.{k}"] = (n, i, o)
        shapes[f"biases.{k}"] = (n, 1, o)
    for name, d in (("in_scaler", config.sizes[0]), ("out_scaler", config.sizes[-1])):
        shapes[f"{name}.mean"] = shapes[f"{name}.std"] = (n, 1, d)
    return shapes


def _check(path: Path, tensors: dict[str, Tensor], expected: dict[str, tuple[int, ...]]) -> None:
    missing, extra = sorted(expected.keys() - tensors.keys()), sorted(tensors.keys() - expected.keys())
    if missing or extra:
        raise ModelFileError(path, f"tensor names do not match the config: missing {missing}, "
                                   f"unexpected {extra}")
    for k, shape in expected.items():
        if tuple(tensors[k].shape) != shape:
            raise ModelFileError(path, f"tensor {k!r} has shape {tuple(tensors[k].shape)}, "
                                       f"the config expects {shape}")


def _read_tensors(tensors_path: Path, device: torch.device | str) -> dict[str, Tensor]:
    if not tensors_path.exists():
        raise ModelFileError(tensors_path, "file not found")
    try:
        return load_file(str(tensors_path), device=str(device))
    except (SafetensorError, OSError) as e:
        raise ModelFileError(tensors_path, f"not a readable safetensors file: {e}") from e


def read_header(json_path: Path, fmt: str = FORMAT) -> dict[str, Any]:
    if not json_path.exists():
        raise ModelFileError(json_path, "metadata file not found")
    try:
        header = json.loads(json_path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise ModelFileError(json_path, f"not valid JSON: {e}") from e
    if not isinstance(header, dict) or header.get("format") != fmt:
        found = header.get("format") if isinstance(header, dict) else None
        raise ModelFileError(json_path, f"not an {fmt} metadata file (format {found!r})")
    if header.get("format_version") != FORMAT_VERSION:
        raise ModelFileError(json_path, f"format_version {header.get('format_version')!r} is not "
                                        f"supported (this code reads {FORMAT_VERSION})")
    return header


SHARED_FORMAT = "anytip.adapted_mlp"


@dataclass
class LoadedShared:
    """What `load_shared` returns: the shared model (with its training units' adapters),
    the training units' input scalers, the output scaler and the saved metadata."""

    model: AdaptedMLP
    in_scaler: Scaler
    out_scaler: Scaler
    meta: dict[str, Any] = field(default_factory=dict)


def save_shared(path: str | Path, model: AdaptedMLP, in_scaler: Scaler, out_scaler: Scaler,
                meta: dict[str, Any] | None = None) -> Path:
    """Write a shared model and its adapters like `save_models` (safetensors + JSON)."""
    tensors = dict(model.state_dict())
    for name, s in (("in_scaler", in_scaler), ("out_scaler", out_scaler)):
        tensors[f"{name}.mean"], tensors[f"{name}.std"] = s.mean, s.std
    header = {"format": SHARED_FORMAT, "config": model.config.model_dump(mode="json"), "kind": model.kind,
              "n_units": model.n_units, "meta": dict(meta or {})}
    return _write_pair(path, tensors, header)


def _write_pair(path: str | Path, tensors: dict[str, Tensor], header: dict[str, Any]) -> Path:
    """`tensors` to `<path>.safetensors` (on the CPU, contiguous) and `header` with the format
    version to its JSON; returns the tensors' path."""
    tensors_path, json_path = model_paths(path)
    tensors_path.parent.mkdir(parents=True, exist_ok=True)
    save_file({k: v.detach().contiguous().cpu() for k, v in tensors.items()}, str(tensors_path))
    write_json(json_path, {"format": header["format"], "format_version": FORMAT_VERSION, **header})
    return tensors_path


def load_shared(path: str | Path, device: torch.device | str = "cpu") -> LoadedShared:
    """Read what `save_shared` wrote; any mismatch raises ModelFileError naming the file."""
    tensors_path, json_path = model_paths(path)
    header = read_header(json_path, SHARED_FORMAT)
    try:
        config, kind, n_units = MLPConfig(**header["config"]), str(header["kind"]), int(header["n_units"])
        model = AdaptedMLP(n_units, config, kind)
    except Exception as e:  # noqa: BLE001 - any bad header is reported the same way
        raise ModelFileError(json_path, f"bad config, kind or n_units: {e}") from e
    tensors = _read_tensors(tensors_path, device)
    expected = {k: tuple(v.shape) for k, v in model.state_dict().items()}
    d_in, d_out = config.sizes[0], config.sizes[-1]
    expected |= {"in_scaler.mean": (n_units, 1, d_in), "in_scaler.std": (n_units, 1, d_in),
                 "out_scaler.mean": (1, 1, d_out), "out_scaler.std": (1, 1, d_out)}
    _check(tensors_path, tensors, expected)
    model.to(device).load_state_dict({k: tensors[k] for k in model.state_dict()})
    return LoadedShared(model, Scaler(tensors["in_scaler.mean"], tensors["in_scaler.std"]),
                        Scaler(tensors["out_scaler.mean"], tensors["out_scaler.std"]),
                        header.get("meta", {}))


RESPONSE_FORMAT = "anytip.response_model"


@dataclass
class LoadedResponse:
    """What `load_response` returns: the response model (with its training units' codes), the
    noise variance (C,) Pa^2 and code spread (k,) a new unit's code fit needs, and the metadata."""

    model: ResponseModel
    noise_var: Tensor
    code_var: Tensor
    meta: dict[str, Any] = field(default_factory=dict)


def save_response(path: str | Path, model: ResponseModel, noise_var: Tensor, code_var: Tensor,
                  meta: dict[str, Any] | None = None) -> Path:
    """Write a response model like `save_models` (safetensors + JSON)."""
    return _write_pair(path, {**model.state_dict(), "noise_var": noise_var, "code_var": code_var},
                       {"format": RESPONSE_FORMAT, "config": model.config.to_json(), "n_units": model.n_units,
                        "n_channels": model.n_channels, "n_labels": int(model.label_mean.shape[0]),
                        "force_cols": model.force_cols.tolist(), "meta": dict(meta or {})})


def load_response(path: str | Path, device: torch.device | str = "cpu") -> LoadedResponse:
    """Read what `save_response` wrote; any mismatch raises ModelFileError naming the file."""
    tensors_path, json_path = model_paths(path)
    header = read_header(json_path, RESPONSE_FORMAT)
    try:
        model = ResponseModel(int(header["n_units"]), int(header["n_channels"]), int(header["n_labels"]),
                              [int(c) for c in header["force_cols"]], ResponseConfig(**header["config"]))
    except Exception as e:  # noqa: BLE001 - any bad header is reported the same way
        raise ModelFileError(json_path, f"bad config, sizes or force columns: {e}") from e
    tensors = _read_tensors(tensors_path, device)
    expected = {k: tuple(v.shape) for k, v in model.state_dict().items()}
    expected |= {"noise_var": (model.n_channels,), "code_var": (model.config.code_dim,)}
    _check(tensors_path, tensors, expected)
    model.to(device).load_state_dict({k: tensors[k] for k in model.state_dict()})
    return LoadedResponse(model, tensors["noise_var"], tensors["code_var"], header.get("meta", {}))


def save_source_response(path: str | Path, digest: str, fitted: Tensor) -> None:
    """Write the training units' own responses to their source rows, fitted (S, C) Pa, under the
    digest of what they were computed from (`train.response.source_digest`), atomically."""
    write_bytes(Path(path), save({"fitted": fitted.detach().contiguous().cpu()}, {"digest": digest}))


def load_source_response(path: str | Path, digest: str, shape: tuple[int, int]) -> Tensor | None:
    """What `save_source_response` wrote, where it was written under `digest`; None where there is no
    such file or it holds another digest. A file that is unreadable, or whose tensor is not `shape`
    finite float32 values, raises ModelFileError naming it."""
    path = Path(path)
    if not path.is_file():
        return None
    try:
        with safe_open(str(path), "pt") as f:
            if (f.metadata() or {}).get("digest") != digest:
                return None
            fitted = f.get_tensor("fitted")
    except (SafetensorError, OSError) as e:
        raise ModelFileError(path, f"not a readable safetensors file: {e}") from e
    if tuple(fitted.shape) != shape or fitted.dtype != torch.float32 or not bool(fitted.isfinite().all()):
        raise ModelFileError(path, f"expected {shape} finite float32 responses, found {tuple(fitted.shape)} "
                                   f"{fitted.dtype}")
    return fitted
