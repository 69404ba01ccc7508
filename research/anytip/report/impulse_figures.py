"""Figures of the analyses: eta maps with isolines (the paper's Fig. 5), a collision trace,
and a stretch of the latency stream. Each function writes one PNG and returns its path.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from anytip.report.figures import save_figure, subplots


def eta_map(x: np.ndarray, y: np.ndarray, eta: np.ndarray, path: Path, xlabel: str, ylabel: str,
            title: str, mark: tuple[float, float] | None = None,
            levels: Sequence[float] = (0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9)) -> Path:
    """eta (len(y), len(x)) as a colour map with labelled isolines; `mark` an (x, y) point."""
    fig, ax = subplots(figsize=(6.4, 4.6))
    im = ax.pcolormesh(x, y, eta, shading="auto", cmap="viridis", vmin=0.0, vmax=1.0)
    fig.colorbar(im, ax=ax, label="impulse ratio eta")
    lines = ax.contour(x, y, eta, levels=list(levels), colors="white", linewidths=0.8)
    ax.clabel(lines, fmt="%.1f", fontsize=8)
    if mark is not None:
        ax.plot(*mark, "r*", ms=12, label="nominal")
        ax.legend(loc="upper right", fontsize=8)
    ax.set(xlabel=xlabel, ylabel=ylabel, title=title)
    return save_figure(fig, path)


def collision_trace(t_closed: np.ndarray, x_closed: np.ndarray, t_num: np.ndarray, x_num: np.ndarray,
                    t_free: np.ndarray, x_free: np.ndarray, t_l: float, path: Path, title: str) -> Path:
    """Spring compression (m) against time (s): closed form, solver points, free sinusoid."""
    fig, ax = subplots(figsize=(6.4, 4))
    ax.plot(t_free * 1e3, x_free * 1e3, "k:", lw=1, label="no actuator (free sinusoid)")
    ax.plot(t_closed * 1e3, x_closed * 1e3, lw=1.5, label="closed form")
    ax.plot(t_num * 1e3, x_num * 1e3, "o", ms=3, mfc="none", label="solve_ivp (DOP853) steps")
    ax.axvline(t_l * 1e3, color="r", lw=0.8, ls="--", label="actuator starts (t_l)")
    ax.axhline(0.0, color="0.5", lw=0.5)
    ax.set(xlabel="time since impact [ms]", ylabel="spring compression x [mm]", title=title)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return save_figure(fig, path)


def stream_excerpt(t_truth: np.ndarray, truth: np.ndarray, t_est: np.ndarray,
                   curves: Mapping[str, np.ndarray], path: Path, title: str,
                   ylabel: str = "normal force Fz [N]") -> Path:
    """Truth (N,) at t_truth (N,) s against estimates, each (M,) at t_est (M,) s."""
    fig, ax = subplots(figsize=(9, 4))
    ax.plot(t_truth, truth, "k", lw=1.2, label="F/T truth (1 kHz)")
    for label, values in curves.items():
        ax.step(t_est, values, where="post", lw=0.9, label=label)
    ax.set(xlabel="time [s]", ylabel=ylabel, title=title)
    ax.legend(fontsize=8, ncol=2)
    ax.grid(alpha=0.3)
    return save_figure(fig, path)
