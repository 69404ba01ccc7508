"""Research log entry 108's question, from runs already scored: over fleet88's 88 held-out units, how the
half-width each unit-output's test rows needed at the floor over its plan's own, log(needed80 / own), repeats
from one scored arm to another (every arm with intervals at 120 s since entry 50: plans, response models,
ordinary use), where SIM40-019 fy and SIM40-006 fy rank in each, and how it relates to the unit's simulated
parameters (Spearman over units, the mean over arms of each arm's centred log ratio). From the repository
root:

    python reports/cross_sensor_response_gpu/entry108/tail_persistence.py
"""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
from scipy.stats import spearmanr

from anytip.rundir import read_json

G = Path("reports/cross_sensor_response_gpu")
ARMS = ("entry50", "entry52", "entry56", "entry58", "entry104/fleet88_cpu_on", "entry104/fleet88_cpu_off",
        "entry106/fleet88_cpu_use")
OUTPUTS = ("fx", "fy", "fz", "theta", "phi")
WATCHED = ("SIM40-019", "SIM40-006")


def log_ratio(row: dict) -> np.ndarray:
    """(D,) a held-out row's log(needed80 / own) per output: how much wider than its plan's own
    half-width its test rows needed the interval at the floor."""
    return np.log([row[f"{o}_needed80_halfwidth"] / row[f"{o}_halfwidth"] for o in OUTPUTS])


def log_ratios(arm: str) -> dict[str, dict[str, np.ndarray]]:
    """Per method of `arm`'s two folds at 120 s: {unit: `log_ratio` (D,)}."""
    out: dict[str, dict[str, np.ndarray]] = {}
    for fold in (0, 1):
        for r in read_json(G / arm / f"fleet88_seed{fold}" / "metrics.json")["results"]:
            if r["method"].startswith("response") and r.get("budget_s") == 120.0 and "fy_halfwidth" in r:
                out.setdefault(r["method"], {})[r["unit"]] = log_ratio(r)
    return out


def unit_parameters(unit: str, registry: Path = Path("data/fleet88")) -> dict[str, float]:
    """Scalar summaries of the unit's simulated parameters, as its first run records them."""
    run = sorted((registry / "runs" / unit).glob("*_o0_*.h5"))[0]
    with h5py.File(run, "r") as f:
        p = json.loads(f.attrs["simulator"])["unit"]
    a = {k: np.asarray(v, float) for k, v in p.items() if isinstance(v, list)}
    return {"hysteresis": p["hysteresis"], "relax_fraction": p["relax_fraction"],
            "relax_tau_s": p["relax_tau_s"], "modulus_pa": p["modulus_pa"],
            "shift_compliance": p["shift_compliance_m_per_n"],
            "bubble_strength": a["bubble_strength"].sum(), "gain_spread": a["channel_gain"].std(),
            "direction_defect": np.abs(a["direction_defect"]).max(),
            "tc_offset": np.abs(a["tc_offset_pa_per_c"]).mean(),
            "tc_gain": np.abs(a["tc_gain_per_c"]).mean(), "noise_pa": a["noise_pa"].mean(),
            "full_scale_min": a["full_scale_pa"].min(), "preload_pa": a["preload_pa"].mean(),
            "temp_sensor_offset": np.abs(a["temp_sensor_offset_c"]).mean(),
            "position_spread": np.linalg.norm(a["baro_positions_m"], axis=1).std()}


def main() -> None:
    arms = {(arm, m): rows for arm in ARMS for m, rows in log_ratios(arm).items()}
    units = sorted(set.intersection(*(set(rows) for rows in arms.values())))
    keys = sorted(arms)
    A = np.stack([[arms[k][u] for u in units] for k in keys])  # (arms, units, outputs)
    A = A - A.mean(1, keepdims=True)
    print(f"{len(keys)} arms, {len(units)} units in all of them")
    upper = np.triu_indices(len(keys), 1)
    for d, o in enumerate(OUTPUTS):
        c = np.corrcoef(A[:, :, d])[upper]
        print(f"{o}: correlation of log(needed80 / own) between arms, median {np.median(c):.2f} "
              f"[{c.min():.2f}, {c.max():.2f}]")
    for u in WATCHED:
        i = units.index(u)
        ranks = ", ".join(f"{a.replace('/fleet88_cpu_', ' ')} {m} {int((A[k, :, 1] > A[k, i, 1]).sum()) + 1}"
                          for k, (a, m) in enumerate(keys))
        print(f"{u} fy rank of {len(units)}: {ranks}")
    params = [unit_parameters(u) for u in units]
    mean = A.mean(0)
    for d, o in enumerate(OUTPUTS):
        rho = sorted(((spearmanr([p[k] for p in params], mean[:, d])[0], k) for k in params[0]),
                     key=lambda t: -abs(t[0]))
        top = ", ".join(f"{k} {r:+.2f}" for r, k in rho[:3])
        print(f"{o}: largest |Spearman| with a unit parameter: {top}")


if __name__ == "__main__":
    main()
