"""Figures for reports: parity plots, error over the contact region, error against force,
training curves. Each function takes plain arrays and writes one PNG.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import FixedLocator, FormatStrFormatter, NullLocator

OUTPUT_NAMES = ("Fx [N]", "Fy [N]", "Fz [N]", "theta [rad]", "phi [rad]")
DPI = 120


def subplots(*grid: int, figsize: tuple[float, float], **kwargs: Any) -> tuple[Figure, Any]:
    """A figure and its axes, like pyplot.subplots, without pyplot's global state or a GUI
    backend (importing this module changes no matplotlib setting)."""
    fig = Figure(figsize=figsize)
    return fig, fig.subplots(*grid, **kwargs)


RATIO_TICKS = (0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 7.0, 10.0, 15.0, 20.0)


def plain_ratio_axis(ax: Any) -> None:
    """A log-scaled ratio axis labelled in plain numbers (0.9, 1, 1.1, 1.5, 2) instead of powers of ten."""
    ax.set_yscale("log")
    ax.yaxis.set_major_locator(FixedLocator(RATIO_TICKS))
    ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.yaxis.set_minor_locator(NullLocator())


def save_figure(fig: Figure, path: Path) -> Path:
    """Lay out and write as PNG at the reports' DPI; returns the path."""
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    return path


def parity(pred: np.ndarray, target: np.ndarray, rmse: Sequence[float], path: Path, title: str,
           max_points: int = 20000, seed: int = 0, labels: Sequence[str] = OUTPUT_NAMES) -> Path:
    """Predicted against true value for each of the D outputs; pred, target (N, D), with each
    output's RMSE over all N rows (`anytip.train.metrics.scores`) and its label ('Fx [N]') in
    its title."""
    idx = np.random.default_rng(seed).permutation(len(pred))[:max_points]
    d = pred.shape[1]
    fig, axes = subplots(1, d, figsize=(3.4 * d, 3.6), squeeze=False)
    for k, ax in enumerate(axes[0]):
        t, p = target[idx, k], pred[idx, k]
        ax.scatter(t, p, s=1, alpha=0.25, rasterized=True)
        lo, hi = float(min(t.min(), p.min())), float(max(t.max(), p.max()))
        ax.plot([lo, hi], [lo, hi], "k--", lw=0.8)
        ax.set(title=f"{labels[k]}  RMSE {rmse[k]:.3g}", xlabel="true", ylabel="predicted")
    fig.suptitle(title)
    return save_figure(fig, path)


def region_heatmap(grid: np.ndarray, t_edges: np.ndarray, p_edges: np.ndarray, path: Path,
                   title: str) -> Path:
    """A value per cell of the contact region: grid (T, P) over theta edges (T+1,) and phi
    edges (P+1,), in degrees."""
    fig, ax = subplots(figsize=(8, 4.2))
    im = ax.pcolormesh(p_edges, t_edges, grid, shading="flat", cmap="viridis")
    fig.colorbar(im, ax=ax, label="RMSE")
    ax.set(xlabel="phi [deg]", ylabel="theta [deg]", title=title, aspect="equal")
    return save_figure(fig, path)


def error_vs_force(centres: np.ndarray, curves: Mapping[str, np.ndarray], path: Path,
                   title: str, ylabel: str = "force RMSE [N]") -> Path:
    """Error against |Fz|: `curves` maps a label to one value per bin centre (N)."""
    fig, ax = subplots(figsize=(6, 4))
    for label, values in curves.items():
        ax.plot(centres, values, "o-", label=label)
    ax.set(xlabel="|Fz| [N]", ylabel=ylabel, title=title)
    ax.legend()
    ax.grid(alpha=0.3)
    return save_figure(fig, path)


def training_curves(histories: Mapping[str, Sequence[tuple[float, float]]], path: Path,
                    title: str, xlabel: str = "epoch", ylabel: str = "validation force RMSE [N]",
                    logy: bool = True) -> Path:
    """One line per label; each history a sequence of (x, y) points."""
    fig, ax = subplots(figsize=(6.5, 4))
    for label, points in histories.items():
        if len(points):
            x, y = zip(*points, strict=True)
            ax.plot(x, y, lw=1, label=label)
    ax.set(xlabel=xlabel, ylabel=ylabel, title=title)
    if logy:
        ax.set_yscale("log")
    if len(histories) <= 12:
        ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return save_figure(fig, path)


def bars(labels: Sequence[str], groups: Mapping[str, Sequence[float]], path: Path, title: str,
         ylabel: str) -> Path:
    """Grouped bars: one group per label, one bar per key of `groups`."""
    x = np.arange(len(labels))
    width = 0.8 / max(1, len(groups))
    fig, ax = subplots(figsize=(max(6, 0.5 * len(labels) + 2), 4))
    for k, (name, values) in enumerate(groups.items()):
        ax.bar(x + k * width, values, width, label=name)
    ax.set_xticks(x + width * (len(groups) - 1) / 2, labels, rotation=45, ha="right", fontsize=8)
    ax.set(ylabel=ylabel, title=title)
    ax.legend()
    ax.grid(axis="y", alpha=0.3)
    return save_figure(fig, path)
