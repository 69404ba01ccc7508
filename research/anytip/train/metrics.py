"""Accuracy in physical units, per unit.

Label columns are the sensor model's targets side by side (the fingertip's: Fx, Fy, Fz
in N, then theta, phi in rad). The torch functions take pred, target (..., N, D) and an
optional mask (..., N) of real rows, and reduce over rows only, so a (U, N, D) input
gives one number per unit.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
import torch
from torch import Tensor

from anytip.data.arrays import OUTPUT_NAMES, TARGET_SLICES, output_names, target_slices
from anytip.data.runfile import V1_LAYOUT, TargetLayout
from anytip.models.scaler import Scaler
from anytip.train.data import pad_rows

FORCE = TARGET_SLICES["force"]
ANGLE = TARGET_SLICES["angles"]


def _mse_per_output(pred: Tensor, target: Tensor, mask: Tensor | None) -> Tensor:
    se = (pred - target).double() ** 2
    if mask is None:
        return se.mean(-2)
    m = mask.unsqueeze(-1).double()
    return (se * m).sum(-2) / m.sum(-2)


def rmse_per_output(pred: Tensor, target: Tensor, mask: Tensor | None = None) -> Tensor:
    """sqrt(mean over rows of squared error) for each output column: (..., N, d) -> (..., d)."""
    return _mse_per_output(pred, target, mask).sqrt()


def force_rmse(pred: Tensor, target: Tensor, mask: Tensor | None = None) -> Tensor:
    """Force RMSE in N: sqrt(mean over rows of the mean over Fx, Fy, Fz of squared error).

    Equals the root of the mean per-axis MSE; the RMSE of the error vector's length,
    sqrt(mean |e|^2), is sqrt(3) times larger. (..., N, 5) -> (...).
    """
    return _mse_per_output(pred[..., FORCE], target[..., FORCE], mask).mean(-1).sqrt()


def force_rmse_per_axis(pred: Tensor, target: Tensor, mask: Tensor | None = None) -> Tensor:
    """RMSE of Fx, Fy, Fz separately, in N: (..., N, 5) -> (..., 3)."""
    return rmse_per_output(pred[..., FORCE], target[..., FORCE], mask)


def angle_rmse(pred: Tensor, target: Tensor, mask: Tensor | None = None) -> Tensor:
    """Angle RMSE in rad: sqrt(mean over rows of the mean over theta, phi of squared error)."""
    return _mse_per_output(pred[..., ANGLE], target[..., ANGLE], mask).mean(-1).sqrt()


def rmse(pred: np.ndarray, target: np.ndarray) -> float:
    """sqrt(mean of squared error) over every element, in float64, in the inputs' unit."""
    return float(np.sqrt(((np.asarray(pred, np.float64) - target) ** 2).mean()))


# The fingertip's targets keep the names its reports have always used.
TARGET_KEYS = {"force": "force_rmse_n", "angles": "angle_rmse_rad"}


def target_key(name: str) -> str:
    """The result key of target `name`'s RMSE: `<name>_rmse` (the fingertip's `force_rmse_n`
    and `angle_rmse_rad`)."""
    return TARGET_KEYS.get(name, f"{name}_rmse")


def target_keys(layout: dict[str, TargetLayout]) -> list[str]:
    """The result keys of every target of `layout`, in layout order."""
    return [target_key(name) for name in layout]


def ratio_fields(row: dict[str, float], reference: dict[str, float],
                 layout: dict[str, TargetLayout] = V1_LAYOUT) -> dict[str, float]:
    """Each target's RMSE in `row` over the same in `reference` (`scores` of one unit's test rows by
    two models), keyed by the stem of its result key: `force_ratio` and `angle_ratio` on the
    fingertip, `<name>_ratio` elsewhere."""
    return {key.split("_rmse")[0] + "_ratio": row[key] / reference[key] for key in target_keys(layout)}


def scores(pred: np.ndarray, target: np.ndarray,
           layout: dict[str, TargetLayout] = V1_LAYOUT) -> dict[str, float]:
    """RMSE of one unit's rows (n, D): per component (`fx_rmse`, ...) and per target over its
    components in the target's unit (`target_key`: `force_rmse_n` in N, `angle_rmse_rad` in
    rad, `position_rmse` in m, ...)."""
    out = {f"{name}_rmse": rmse(pred[:, k], target[:, k]) for k, name in enumerate(output_names(layout))}
    for name, cols in target_slices(layout).items():
        out[target_key(name)] = rmse(pred[:, cols], target[:, cols])
    return out


def binned_rmse(err2: np.ndarray, bins: np.ndarray, n_bins: int) -> np.ndarray:
    """RMSE within each bin: err2 (N,) squared errors, bins (N,) int bin of each row (rows
    outside 0..n_bins-1 are left out) -> (n_bins,) float64, NaN where a bin is empty."""
    keep = (bins >= 0) & (bins < n_bins)
    total = np.bincount(bins[keep], weights=err2[keep], minlength=n_bins)
    count = np.bincount(bins[keep], minlength=n_bins)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.sqrt(total / count)


def region_rmse(angles: np.ndarray, err2: np.ndarray,
                cell_deg: float = 7.5) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """RMSE over the sensing region (theta in [-45, 45] deg, phi in [-135, 45] deg) in square
    cells: angles (N, 2) rad, err2 (N,) -> (grid (T, P), theta edges (T+1,), phi edges (P+1,)),
    edges in degrees; a cell without rows is NaN."""
    deg = np.degrees(angles)
    t_edges = np.arange(-45, 45 + cell_deg, cell_deg)
    p_edges = np.arange(-135, 45 + cell_deg, cell_deg)
    t = np.digitize(deg[:, 0], t_edges) - 1
    p = np.digitize(deg[:, 1], p_edges) - 1
    T, P = len(t_edges) - 1, len(p_edges) - 1
    inside = (t >= 0) & (t < T) & (p >= 0) & (p < P)
    bins = np.where(inside, t * P + p, -1)
    return binned_rmse(err2, bins, T * P).reshape(T, P), t_edges, p_edges


def rmse_by_level(level: np.ndarray, err2: np.ndarray, n_bins: int = 10) -> tuple[np.ndarray, np.ndarray]:
    """RMSE in `n_bins` equal bins of |level| from 0 to its maximum (e.g. normal force in N):
    level, err2 (N,) -> (bin centres (n_bins,), RMSE (n_bins,), NaN where empty)."""
    mag = np.abs(level)
    edges = np.linspace(0, max(float(mag.max()), 1e-6), n_bins + 1)
    which = np.clip(np.digitize(mag, edges) - 1, 0, n_bins - 1)
    return 0.5 * (edges[1:] + edges[:-1]), binned_rmse(err2, which, n_bins)


@torch.no_grad()
def predict(model: Callable[[Tensor], Tensor], in_scaler: Scaler, out_scaler: Scaler, X: Tensor,
            chunk_elems: int = 1 << 22) -> Tensor:
    """Physical predictions (U, N, 5) for physical inputs X (U, N, 8), in row chunks.

    Chunks hold about `chunk_elems` activations of the widest layer, which bounds memory.

    `model` maps standardised (U, B, 8) to standardised (U, B, 5): a BatchedMLP, or an
    nn.Sequential when U == 1.
    """
    U, N, _ = X.shape
    config = getattr(model, "config", None)
    width = max(config.sizes) if config is not None else 64
    rows = max(1, chunk_elems // (U * width))
    parts = [out_scaler.inverse(model(in_scaler.transform(X[:, i : i + rows])))
             for i in range(0, N, rows)]
    return torch.cat(parts, dim=1)


def evaluate(model: Callable[[Tensor], Tensor], in_scaler: Scaler, out_scaler: Scaler,
             X: Tensor | Sequence[Tensor], Y: Tensor | Sequence[Tensor],
             n: Tensor | None = None) -> dict[str, Tensor]:
    """Per-unit accuracy of every unit on its own rows.

    X, Y: lists of per-unit (n_u, 8) / (n_u, 5) tensors, or padded (U, N, .) with counts n (U,).
    Returns float64 tensors: rmse (U, D) per output, loss (U,) = MSE on standardised outputs
    (what training minimises), and for the fingertip's 5 columns force_rmse (U,) N and
    angle_rmse (U,) rad.
    """
    if not isinstance(X, Tensor):
        device = out_scaler.mean.device
        X, n = pad_rows(X, device)
        Y, _ = pad_rows(Y, device)
    mask = None if n is None else torch.arange(X.shape[1], device=X.device) < n[:, None]
    pred = predict(model, in_scaler, out_scaler, X)
    loss = _mse_per_output(out_scaler.transform(pred), out_scaler.transform(Y), mask).mean(-1)
    out = {"rmse": rmse_per_output(pred, Y, mask), "loss": loss}
    if Y.shape[-1] == len(OUTPUT_NAMES):  # the fingertip's columns: its two headline figures
        out |= {"force_rmse": force_rmse(pred, Y, mask), "angle_rmse": angle_rmse(pred, Y, mask)}
    return out


def history_fields(val: dict[str, Tensor], unit: int | None = None) -> dict[str, object]:
    """A history row's validation figures from `evaluate`: the fingertip's val_force_rmse (N)
    and val_angle_rmse (rad), else val_rmse per output; per-unit lists, or unit `unit`'s."""
    keys = [k for k in ("force_rmse", "angle_rmse") if k in val] or ["rmse"]
    return {f"val_{k}": (val[k].tolist() if unit is None else val[k][unit].tolist()) for k in keys}


def progress_text(val: dict[str, Tensor]) -> str:
    """One progress-bar phrase: mean validation force RMSE, or the loss for other targets."""
    if "force_rmse" in val:
        return f"val force {val['force_rmse'].mean():.3f} N"
    return f"val loss {val['loss'].mean():.3f}"
