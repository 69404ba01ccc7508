"""Research log entry 94's diagnostic: is the Laplace posterior of a plan's codes as wide as their error?
`scripts/rescore_response.py` stopped before any network trains: for every validation and held-out unit,
its codes fitted on its plan and their covariance (`code_covariance`), and the codes fitted on its whole
calibration outside its test patches (entry 87's oracle, which the plan's codes should lie near if the
plan's error is the uncertainty the posterior describes). Per unit and barometer, the squared Mahalanobis
distance of the oracle codes from the plan's, over the code's k dimensions (about 1 for a posterior as
wide as the error, much more for one too narrow), and in pressure over the whole calibration's rows: the
RMS of G(y; oracle) - G(y; plan) against the RMS the posterior predicts for it (the linearised spread,
from 16 draws). And whether a plan's errors are shared within a press: the residuals of its rows about the
response with the oracle codes, per press and barometer, their mean's variance over presses against the
within-press variance over the press's rows (about 1 for independent rows, the rows a press is worth
if far more). Prints each and writes OUT/posterior_check.json. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry94/posterior_check.py RUN --registry REG \\
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
from anytip.train.response import code_covariance, drawn_codes, evenly_spaced, fit_codes, respond

ORACLE_ROWS = 16384
SCORE_ROWS = 4096  # of the whole calibration, evenly spaced, where the pressures are compared
DRAWS = 16


def press_sharing(fit, X: torch.Tensor, Y: torch.Tensor, bounds: np.ndarray, codes: torch.Tensor) -> dict:
    """The residuals of rows X (n, C) Pa, Y (n, D) about the response with codes (C, k), in presses
    [bounds[p], bounds[p + 1]): the variance over presses of each press's mean residual against the mean
    within-press variance over its row count (pooled over barometers), and both as Pa."""
    resid = (X - respond(fit.model, Y, codes)).numpy()
    means, within = [], []
    for a, b in zip(bounds[:-1], bounds[1:], strict=True):
        if b - a > 1:
            means.append(resid[a:b].mean(0))
            within.append(resid[a:b].var(0, ddof=1) / (b - a))
    between = np.var(np.array(means), 0, ddof=1)  # (C,)
    expected = np.mean(np.array(within), 0)  # (C,)
    return {"between_press_var_pa2": between.tolist(), "within_over_rows_var_pa2": expected.tolist(),
            "sharing": float(np.mean(between) / np.mean(expected))}


class Stop(Exception):
    """Raised once the numbers are written: no network is trained."""


def pressure_gap(fit, Y: torch.Tensor, codes: torch.Tensor, other: torch.Tensor) -> float:
    """Pa: RMS over rows Y (n, D) and barometers of G(y; other) - G(y; codes), codes (C, k) each."""
    return float((respond(fit.model, Y, other) - respond(fit.model, Y, codes)).pow(2).mean().sqrt())


def check(ctx, arrays, sd, fit, carry, recipe, jobs, seed, codes=None, extra=None):
    """Each plan-calibrated job's codes, their covariance and its unit's oracle codes, compared."""
    if codes is not None:  # the with-use jobs: not this diagnostic's
        return pipe_calibrated(ctx, arrays, sd, fit, carry, recipe, jobs, seed, codes, extra)
    X = [torch.from_numpy(arrays.pressure[p.rows]) for _, _, p in jobs]
    Y = [torch.from_numpy(arrays.targets[p.rows]) for _, _, p in jobs]
    n_eff = [p.n_effective for _, _, p in jobs]
    planned = fit_codes(fit, X, Y, n_eff, recipe, seed)
    cov = code_covariance(fit, X, Y, n_eff, planned, recipe)
    units = sorted({u for u, _, _ in jobs})
    rows = [sd.evals[u].presses.rows for u in units]
    Xa = [torch.from_numpy(arrays.pressure[r]) for r in rows]
    Ya = [torch.from_numpy(arrays.targets[r]) for r in rows]
    whole_eff = [min(len(r), float(sd.evals[u].presses.duration_s.sum()) * 10.0)
                 for u, r in zip(units, rows, strict=True)]
    oracle = fit_codes(fit, Xa, Ya, whole_eff, replace(recipe, code_rows=ORACLE_ROWS), seed)
    out = {}
    for m, (u, b, p) in enumerate(jobs):
        i = units.index(u)
        d = (oracle[i] - planned[m]).double()
        maha = torch.einsum("ck,ckj,cj->c", d, torch.linalg.inv(cov[m].double()), d) / d.shape[-1]
        Ys = Ya[i][evenly_spaced(len(Ya[i]), SCORE_ROWS)]
        draws = drawn_codes(planned[m], cov[m], 1.0, DRAWS, seed + m)
        spread = np.sqrt(np.mean([pressure_gap(fit, Ys, planned[m], z) ** 2 for z in draws]))
        out.setdefault(b.strategy, {})[u] = {
            "role": "val" if u in sd.split.val else "test",
            "mahalanobis_per_dim": maha.tolist(),
            "oracle_gap_pa": pressure_gap(fit, Ys, planned[m], oracle[i]),
            "posterior_spread_pa": float(spread),
            "press_residuals": press_sharing(fit, X[m], Y[m], p.bounds, oracle[i])}
    path = Path(ctx.run_dir) / "posterior_check.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"seed": seed, "by_strategy": out}, indent=1))
    for strategy, by_unit in out.items():
        for role in ("val", "test"):
            got = [v for v in by_unit.values() if v["role"] == role]
            if got:
                maha = np.median([np.median(v["mahalanobis_per_dim"]) for v in got])
                ratio = np.mean([v["oracle_gap_pa"] / v["posterior_spread_pa"] for v in got])
                sharing = np.median([v["press_residuals"]["sharing"] for v in got])
                print(f"{strategy} {role}: {len(got)} units, median Mahalanobis^2 per dim {maha:.2f}, "
                      f"oracle gap / posterior spread in pressure {ratio:.2f}, press means' variance over "
                      f"independent rows' {sharing:.1f}", flush=True)
    raise Stop


pipe_calibrated = pipe.calibrated
pipe.calibrated = check
sys.argv[0] = "scripts/rescore_response.py"
try:
    runpy.run_path("scripts/rescore_response.py", run_name="__main__")
except Stop:
    pass
