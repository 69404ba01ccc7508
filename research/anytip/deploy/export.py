"""`anytip export`: one unit of a model file to onnx, c, c-int8, firmware (or an anytip model file,
for firmware nets read from JSON), each with a JSON verification report `verification.json`.

Every check compares against the trained model evaluated in float64 on reference rows (registry
rows of the unit, or synthetic inputs, see `anytip.deploy.reference`). A float32 export passes when
every output on every row lies within the float32 rounding error bound of the network exported
(`anytip.deploy.rounding`, evaluated on that row); int8 C against numpy's int8 model within one
activation step of its last layer. Each report gives the largest error, bound and their ratio.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from anytip.data.runfile import TargetLayout
from anytip.deploy import embedded, firmware
from anytip.deploy.c_export import buffer_width, c_parameters, c_table, write_c
from anytip.deploy.c_int8 import write_c_int8
from anytip.deploy.held_out import HeldOut, parse_spec
from anytip.deploy.held_out import for_model as held_out_for
from anytip.deploy.held_out import from_run as held_out_from_run
from anytip.deploy.native import run_c
from anytip.deploy.net import DeployNet, deploy_net, model_predict, require_relu, unit_index
from anytip.deploy.onnx_export import float32_parameters, onnx_parameters, run_onnx, write_onnx
from anytip.deploy.quantize import QuantNet, quantize, simulate
from anytip.deploy.reference import Reference, registry_reference, synthetic_reference
from anytip.deploy.rounding import U_FLOAT32, U_FLOAT64, check, network_tolerance
from anytip.errors import AnytipError
from anytip.models.io import LoadedModels, load_models, save_models
from anytip.rundir import write_json
from anytip.train.metrics import scores as target_scores
from anytip.train.metrics import target_keys

FORMATS = ("onnx", "c", "c-int8", "firmware", "model")
INT8_RMSE_TARGET = 0.02  # int8 RMSE increase over float, as a fraction of the float RMSE
EMU_ROWS = 3  # rows run through the emulator (each counts one inference)


def load_any(path: str | Path) -> LoadedModels:
    """An anytip model file, or a firmware nets JSON (deployed_nets.json layout) imported on the fly."""
    path = Path(path)
    if path.suffix == ".json" and _is_firmware_json(path):
        return firmware.import_firmware(firmware.read_firmware_json(path))
    return load_models(path)


def _is_firmware_json(path: Path) -> bool:
    try:
        doc = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError):
        return False
    return isinstance(doc, dict) and isinstance(doc.get("units"), dict)


def errors(y: np.ndarray, ref: np.ndarray, net: DeployNet, x: np.ndarray, copies: int = 1) -> dict[str, Any]:
    """Outputs y (B, out) of a float32 export of `net` on rows x against the float64 reference:
    passed when every error lies within the float32 rounding bound (`copies` exports compared
    with each other: each may err by the bound)."""
    return check(y, ref, copies * network_tolerance(net, x), net.out_scale)


def parameters(found: np.ndarray, expected: np.ndarray) -> dict[str, Any]:
    """Does an export hold exactly the float32 parameters of the network? Every value compared
    bit for bit: a changed weight is caught here even where its effect on the outputs hides
    within the rounding bound."""
    found, expected = np.asarray(found, np.float32).ravel(), np.asarray(expected, np.float32).ravel()
    if found.shape != expected.shape:
        return {"count": int(expected.size), "found": int(found.size), "passed": False}
    differ = found.view(np.uint32) != expected.view(np.uint32)
    diff = np.abs(found.astype(np.float64) - expected)
    return {"count": int(expected.size), "differing": int(differ.sum()),
            "max_abs_diff": float(diff.max(initial=0.0)), "passed": not differ.any()}


def int8_tolerance(q: QuantNet, y: np.ndarray) -> np.ndarray:
    """(B, out) how far two evaluations of one int8 network may differ: one int16 step of any one
    input of its last layer (a rounding tie resolved the other way upstream), plus the float32
    rescale's own rounding of y (B, out)."""
    last = q.layers[-1]
    step = np.abs(last.q_w.astype(np.float64)).max(0) * np.abs(last.mult.astype(np.float64))
    return step[None, :] + 4 * U_FLOAT32 * np.abs(y)


def rmse(y: np.ndarray, t: np.ndarray, layout: dict[str, TargetLayout]) -> dict[str, float]:
    """Each target's RMSE (`force_rmse_n`, `angle_rmse_rad`, `position_rmse`, ...) of outputs y
    (n, d or 2d) against targets t (n, d) laid out as `layout`. A heteroscedastic model's d means
    come first (its scale outputs follow), so they are scored."""
    s = target_scores(y[:, : t.shape[1]], t, layout)
    return {key: s[key] for key in target_keys(layout)}


def int8_accuracy(y_q: np.ndarray, y_f: np.ndarray, ref: Reference, ev: np.ndarray) -> dict[str, Any]:
    """RMSE of float and int8 against the targets (or int8 against float when there are none)."""
    if ref.targets is None:
        out = {"against": "float model (no targets)", "int8_vs_float": rmse(y_q, y_f, ref.layout)}
        return out | {"passed": True, "note": "no targets: the RMSE increase is not defined"}
    f, q = rmse(y_f, ref.targets[ev], ref.layout), rmse(y_q, ref.targets[ev], ref.layout)
    inc = {k: (q[k] - f[k]) / f[k] for k in f}
    return {"against": "targets", "float": f, "int8": q, "rmse_increase": inc,
            "target_increase": INT8_RMSE_TARGET, "passed": max(inc.values()) <= INT8_RMSE_TARGET}


def scores(y: np.ndarray, ref: Reference, rows: np.ndarray | None = None) -> dict[str, float] | None:
    """Force and angle RMSE against the reference targets on `rows` (default: the scored rows)."""
    if ref.targets is None:
        return None
    rows = ref.eval_rows if rows is None else rows
    return rmse(np.asarray(y)[rows], ref.targets[rows], ref.layout)


def measure(source: Path, net: DeployNet, x: np.ndarray, expect: np.ndarray, work: Path,
            includes: tuple[str, ...] = (), strict: bool = True) -> dict[str, Any]:
    """Cortex-M4F section sizes, emulated instructions per inference and the emulator's outputs."""
    why = embedded.toolchain_missing()
    if why:
        return {"skipped": why}
    out: dict[str, Any] = embedded.cross_compile(source, work / "cortex-m4", includes, strict)
    why = embedded.emulator_missing()
    if why:
        return out | {"emulator_skipped": why}
    counts, ys = zip(*(embedded.count_instructions(source, r, net.n_outputs, includes, strict)
                       for r in x[:EMU_ROWS]), strict=True)
    out |= {"instructions": int(max(counts)), "macs": net.macs,
            "instructions_per_mac": float(max(counts)) / net.macs,
            "emulated_vs_host": errors(np.array(ys), expect[:EMU_ROWS], net, x[:EMU_ROWS], copies=2)}
    return out


@dataclass
class Prepared:
    """One unit of a model, folded, with its reference rows and the trained model's outputs on them."""

    model: str
    loaded: LoadedModels
    index: int
    net: DeployNet
    ref: Reference
    y_model: np.ndarray  # (B, 5) the trained model in float64 on ref.x


def prepare(model: str | Path, unit: str | None = None, registry=None, rows: int = 20000,
            held_out: HeldOut | str | None = "auto") -> Prepared:
    """Load `model` (or import a firmware JSON), pick `unit`, fold it and choose reference rows: the
    unit's registry rows the model never trained on (`held_out`; "auto": what the model file's run
    directory or metadata tell; "RUN_DIR[:SEED]": what that run held out, see
    `anytip.deploy.held_out`; None: all its rows), or synthetic inputs without a registry."""
    loaded = load_any(model)
    index = unit_index(loaded, unit, model)
    net = deploy_net(loaded, index, model)
    why = ""
    if held_out == "auto":
        held_out, why = held_out_for(model, loaded, index, net.unit, registry)
    elif isinstance(held_out, str):
        held_out = held_out_from_run(*parse_spec(held_out), net.unit, index, registry)
    ref = (registry_reference(registry, net.unit, rows, held_out=held_out)
           if registry is not None else None) or synthetic_reference(net, min(rows, 4000))
    if ref.may_include_training_rows and why:
        ref.note += f"; no held-out rows known: {why}"
    return Prepared(str(model), loaded, index, net, ref, model_predict(loaded, index, ref.x))


def export_model(model: str | Path, fmt: str, out_dir: str | Path, unit: str | None = None,
                 registry=None, rows: int = 20000, embedded_checks: bool = True,
                 held_out: HeldOut | str | None = "auto") -> dict[str, Any]:
    """Export one unit in `fmt` into out_dir and write out_dir/verification.json; returns the report."""
    if fmt not in FORMATS:
        raise AnytipError(f"--format {fmt!r} is not one of {', '.join(FORMATS)}")
    return export_prepared(prepare(model, unit, registry, rows, held_out), fmt, out_dir, embedded_checks)


def export_prepared(p: Prepared, fmt: str, out_dir: str | Path,
                    embedded_checks: bool = True) -> dict[str, Any]:
    """`export_model` on an already prepared unit."""
    if fmt not in FORMATS:
        raise AnytipError(f"--format {fmt!r} is not one of {', '.join(FORMATS)}")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    net = p.net
    report: dict[str, Any] = {"format": fmt, "model": p.model, "unit": net.unit,
                              "output_names": net.output_names, "output_scale": net.out_scale.tolist(),
                              "params": net.n_params, "macs": net.macs, "reference": p.ref.describe()}
    report |= EXPORTERS[fmt](p.loaded, p.index, net, p.ref, p.y_model, out_dir, embedded_checks)
    report["passed"] = _all_passed(report)
    write_json(out_dir / "verification.json", report)
    return report


def _all_passed(report: dict[str, Any]) -> bool:
    flags = []

    def walk(d: Any) -> None:
        if isinstance(d, dict):
            for k, v in d.items():
                if k == "passed" and isinstance(v, bool):
                    flags.append(v)
                else:
                    walk(v)
    walk({k: v for k, v in report.items() if k != "passed"})
    return all(flags) and bool(flags)


def verify_onnx(path: Path, net: DeployNet, ref: Reference, y_model: np.ndarray) -> dict[str, Any]:
    """An ONNX file against `net`: its parameters bit for bit, its outputs within the bound."""
    y = run_onnx(path, ref.x)
    return {"parameters": parameters(onnx_parameters(path), float32_parameters(net)),
            "onnxruntime": errors(y, y_model, net, ref.x), "scores": scores(y, ref)}


def _onnx(loaded, index, net, ref, y_model, out_dir, emb) -> dict[str, Any]:
    path = write_onnx(net, out_dir)
    return {"files": [path.name], **verify_onnx(path, net, ref, y_model)}


def verify_c(source: Path, net: DeployNet, ref: Reference, y_model: np.ndarray) -> dict[str, Any]:
    """A float32 C file against `net`, compiled on the host: parameters and outputs."""
    y_c = run_c(source, ref.x, net.n_outputs)
    return {"parameters": parameters(c_parameters(source), c_table(net)),
            "gcc_host": errors(y_c, y_model, net, ref.x), "scores": scores(y_c, ref), "y": y_c}


def _c(loaded, index, net, ref, y_model, out_dir, emb) -> dict[str, Any]:
    h, c = write_c(net, out_dir)
    checked = verify_c(c, net, ref, y_model)
    y_c = checked.pop("y")
    rep = {"files": [h.name, c.name], **checked,
           "activation_buffer_floats": 2 * buffer_width(net)}
    if emb:
        rep["cortex_m4"] = measure(c, net, ref.x, y_c, out_dir / "build")
    return rep


def quantize_reference(net: DeployNet, ref: Reference, y_model: np.ndarray):
    """The int8 network calibrated on the reference's calibration rows (disjoint from the scored
    rows); its rounding weighs each output by the float model's RMSE there when there are targets
    (a heteroscedastic model's scale outputs, which have no target, by their own spread)."""
    require_relu(net, "c-int8")
    err_scale = None
    if ref.targets is not None:  # the float model's RMSE per output on the calibration rows
        y, d = y_model[ref.cal], ref.targets.shape[1]
        spread = np.maximum(y[:, d:].std(0), 1e-6)
        err_scale = np.concatenate([np.sqrt(((y[:, :d] - ref.targets[ref.cal]) ** 2).mean(0)), spread])
    return quantize(net, ref.x[ref.cal], err_scale)


def _c_int8(loaded, index, net, ref, y_model, out_dir, emb) -> dict[str, Any]:
    q = quantize_reference(net, ref, y_model)
    h, c = write_c_int8(q, net, out_dir)
    ev = ref.eval_rows
    y_c = run_c(c, ref.x[ev], net.n_outputs, fused=False)  # numpy's int8 model rounds every step
    y_sim = simulate(q, ref.x[ev])
    rep = {"files": [h.name, c.name], "quantization": "per-channel symmetric int8 weights (GPTQ rounding, "
           "bias correction, greedy rounding search), int16 activations, int32 accumulation",
           "gcc_host_vs_numpy_int8": check(y_c, y_sim, int8_tolerance(q, y_sim), net.out_scale),
           "int8_vs_float_max_abs_err": np.abs(y_c - y_model[ev]).max(0).tolist(),
           "accuracy": int8_accuracy(y_c, y_model[ev], ref, ev),
           "scores": None if ref.targets is None else rmse(y_c, ref.targets[ev], ref.layout)}
    if emb:
        rep["cortex_m4"] = measure(c, net, ref.x[ev], y_c, out_dir / "build")
    return rep


def _firmware(loaded, index, net, ref, y_model, out_dir, emb) -> dict[str, Any]:
    if net.output_names and tuple(net.output_names) != firmware.FINGERTIP_OUTPUTS:
        raise AnytipError(f"the firmware struct is the fingertip's ({', '.join(firmware.FINGERTIP_OUTPUTS)}; "
                          f"8 barometers); this model outputs {', '.join(net.output_names)} from "
                          f"{net.n_inputs} barometers: export it as onnx or c instead")
    require_relu(net, "firmware")
    nets = {net.unit: firmware.to_firmware(loaded, index, net, ref.x, targets=ref.targets)}
    path = firmware.write_firmware_json(out_dir / "firmware.json", nets, firmware.DESCRIPTION)
    c_path = firmware.write_firmware_c(out_dir / "anytip_firmware_net.c", nets[net.unit], net.unit)
    back = firmware.read_firmware_json(path)[net.unit]
    y_fw = firmware.to_rad(firmware.firmware_forward(back, ref.x))
    clipped = firmware.clipped_outputs(back, ref.x)
    fw_tol = firmware.firmware_tolerance(back, ref.x)
    return {"files": [path.name, c_path.name],
            "firmware_direct": check(y_fw, y_model, fw_tol, net.out_scale),
            "scores": scores(y_fw, ref),
            "output_relu": {"clipped_outputs_on_reference": clipped,
                            "passed": clipped == 0 or net.output_relu,
                            "minims": back["minims"][:firmware.N_OUT].tolist(),
                            "maxims": back["maxims"][:firmware.N_OUT].tolist()}}


def _model(loaded, index, net, ref, y_model, out_dir, emb) -> dict[str, Any]:
    one = LoadedModels(loaded.model.model_slice(index), loaded.in_scaler.slice(index),
                       loaded.out_scaler.slice(index), _slice_meta(loaded.meta, index))
    path = save_models(out_dir / "model.safetensors", one.model, one.in_scaler, one.out_scaler, one.meta)
    back = load_models(path)
    tolerance = network_tolerance(net, ref.x, U_FLOAT64)
    return {"files": [path.name, path.with_suffix(".json").name],
            "reloaded": check(model_predict(back, 0, ref.x), y_model, tolerance, net.out_scale)}


def _slice_meta(meta: dict[str, Any], index: int) -> dict[str, Any]:
    out = dict(meta)
    out["unit_ids"] = [meta["unit_ids"][index]] if meta.get("unit_ids") else None
    if "firmware" in meta and out["unit_ids"]:
        out["firmware"] = {u: meta["firmware"][u] for u in out["unit_ids"] if u in meta["firmware"]}
    return {k: v for k, v in out.items() if v is not None}


EXPORTERS = {"onnx": _onnx, "c": _c, "c-int8": _c_int8, "firmware": _firmware, "model": _model}
