"""Research log entry 90's diagnostic: how well each plan's codes describe its unit's whole calibration.
`scripts/rescore_response.py` stopped before any network trains: for every validation and held-out
unit, its codes fitted on each of its plans (as `response@` fits them) and on its whole calibration
outside its test patches (entry 87's oracle), then the RMS of the unit's pressures about the response
with those codes over every calibration row outside the test patches, in bands of |F|. Prints one line
per (plan, band) and writes the numbers to OUT/code_residuals.json. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry90/code_residuals.py RUN --registry REG \\
        --out OUT [rescore_response.py's options]
"""

import json
import runpy
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import torch

import anytip.pipelines.cross_sensor_response as pipe
from anytip.train.response import fit_codes, respond

BANDS = (0.0, 3.0, 7.0, 13.0, 19.0, np.inf)  # |F|, N
ORACLE_ROWS = 16384


class Stop(Exception):
    """Raised once the residuals are written: no network is trained."""


def band_rms(fit, X: torch.Tensor, Y: torch.Tensor, codes: torch.Tensor) -> list[float]:
    """Pa: RMS over rows and barometers of X (n, C) about the response with codes (C, k), per |F| band."""
    with torch.no_grad():
        resid = (X - respond(fit.model, Y, codes)).pow(2).mean(1).numpy()
    force = Y[:, :3].norm(dim=1).numpy()
    band = np.digitize(force, BANDS) - 1
    return [float(np.sqrt(resid[band == b].mean())) if (band == b).any() else float("nan")
            for b in range(len(BANDS) - 1)]


def residuals(ctx, arrays, sd, fit, carry, recipe, jobs, seed, codes=None, extra=None):
    """Each job's codes and its unit's oracle codes, scored on the unit's whole calibration."""
    X = [torch.from_numpy(arrays.pressure[p.rows]) for _, _, p in jobs]
    Y = [torch.from_numpy(arrays.targets[p.rows]) for _, _, p in jobs]
    planned = fit_codes(fit, X, Y, [p.n_effective for _, _, p in jobs], recipe, seed)
    units = sorted({u for u, _, _ in jobs})
    rows = [sd.evals[u].presses.rows for u in units]
    Xa = [torch.from_numpy(arrays.pressure[r]) for r in rows]
    Ya = [torch.from_numpy(arrays.targets[r]) for r in rows]
    n_eff = [min(len(r), float(sd.evals[u].presses.duration_s.sum()) * 10.0)
             for u, r in zip(units, rows, strict=True)]
    oracle = fit_codes(fit, Xa, Ya, n_eff, replace(recipe, code_rows=ORACLE_ROWS), seed)
    out, force = {}, {}
    for m, (u, b, p) in enumerate(jobs):
        i = units.index(u)
        out.setdefault(b.strategy, {})[u] = band_rms(fit, Xa[i], Ya[i], planned[m])
        per_press = np.add.reduceat(Y[m][:, :3].norm(dim=1).numpy(), p.bounds[:-1]) / np.diff(p.bounds)
        force.setdefault(b.strategy, {})[u] = np.sort(per_press).round(2).tolist()
    out["oracle"] = {u: band_rms(fit, Xa[i], Ya[i], oracle[i]) for i, u in enumerate(units)}
    path = Path(ctx.run_dir) / "code_residuals.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"bands_n": [b if np.isfinite(b) else None for b in BANDS], "seed": seed,
                                "val": list(sd.split.val), "rms_pa": out,
                                "press_mean_force_n": force}, indent=1))
    for name, by_unit in out.items():
        low = np.mean([np.mean(np.array(f) < 7) for f in force.get(name, {}).values()] or [np.nan])
        print(f"{name:12s} " + " ".join(f"{v:7.1f}" for v in np.nanmean(list(by_unit.values()), 0))
              + f"  presses under 7 N: {low:.0%}", flush=True)
    raise Stop


pipe.calibrated = residuals
sys.argv[0] = "scripts/rescore_response.py"
try:
    runpy.run_path("scripts/rescore_response.py", run_name="__main__")
except Stop:
    pass
