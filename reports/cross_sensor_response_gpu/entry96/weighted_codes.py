"""Research log entry 96: `scripts/rescore_response.py` with every plan-calibrated job's codes fitted on
rows weighted so that their distribution over label cells matches the source rows' (the training units'
rows the transfer carries over): a cell's weight is the source share over the plan's share (the source
share renormalised over the cells the plan holds), clipped at MAX_WEIGHT, normalised to mean 1 over the
job's rows, and every row's weight times Kish's effective fraction (sum w)^2 / (n sum w^2). Codes from the
joint fit with ordinary use are not weighted. The unit's network then trains as `response@` does.
Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry96/weighted_codes.py CELLS RUN --registry REG --out OUT \\
        [rescore_response.py's options]

CELLS: `f` (|F| bands) or `fp` (|F| bands times three quantile bins of each other target).
"""

import runpy
import sys

import numpy as np
import torch

import anytip.pipelines.cross_sensor_response as pipe
import anytip.train.response as response

FORCE_BANDS = torch.tensor([3.0, 7.0, 13.0, 19.0])  # N: entry 90's bands' inner edges
PLACE_BINS = 3  # quantile bins of each non-force target (`fp`)
MAX_WEIGHT = 10.0


class Cells:
    """Label cells: |F| band, and with `place` a quantile bin of each non-force target."""

    def __init__(self, source_Y: torch.Tensor, force_cols: list[int], place: bool):
        self.force_cols = force_cols
        self.other = [c for c in range(source_Y.shape[1]) if c not in force_cols] if place else []
        q = torch.linspace(0, 1, PLACE_BINS + 1)[1:-1]
        self.edges = [torch.quantile(source_Y[:, c].float(), q) for c in self.other]
        self.n_cells = (len(FORCE_BANDS) + 1) * PLACE_BINS ** len(self.other)
        self.target = torch.bincount(self(source_Y), minlength=self.n_cells).float()
        self.target /= self.target.sum()

    def __call__(self, Y: torch.Tensor) -> torch.Tensor:
        """(n,) each row's cell of labels Y (n, D)."""
        cell = torch.bucketize(Y[:, self.force_cols].norm(dim=1), FORCE_BANDS.to(Y.device))
        for c, e in zip(self.other, self.edges, strict=True):
            cell = cell * PLACE_BINS + torch.bucketize(Y[:, c].contiguous(), e.to(Y.device))
        return cell


def row_weights(cells: Cells, Y: torch.Tensor) -> tuple[torch.Tensor, float]:
    """(n,) importance weights of rows with labels Y (n, D), mean 1, and Kish's effective fraction."""
    cell = cells(Y)
    plan = torch.bincount(cell, minlength=cells.n_cells).float()
    target = cells.target.to(Y.device) * (plan > 0)
    ratio = (target / target.sum()) / (plan / plan.sum()).clamp_min(1e-12)
    w = ratio[cell].clamp(max=MAX_WEIGHT)
    w = w / w.mean()
    return w, float(w.sum() ** 2 / (len(w) * (w ** 2).sum()))


STATE: dict = {"cells": None, "kish": []}


def weighted_problem(fit, X, Y, n_effective, recipe):
    """`_plan_problem`, each job's rows weighted by `row_weights` while `STATE['cells']` is set."""
    problem = plain_problem(fit, X, Y, n_effective, recipe)
    cells = STATE["cells"]
    if cells is None:
        return problem
    row_w = problem.row_w.clone()
    for m in range(len(X)):
        valid = row_w[m, :, 0] > 0
        if not bool(valid.any()):
            continue
        w, kish = row_weights(cells, problem.Yp[m, valid])
        row_w[m, valid] *= (w * kish)[:, None]
        STATE["kish"].append(kish)
    return problem._replace(row_w=row_w)


def with_weights(ctx, arrays, sd, fit, carry, recipe, jobs, seed, codes=None, extra=None):
    """`calibrated`, its jobs' codes (where not given) fitted on importance-weighted rows."""
    if codes is None:
        cells = Cells(carry[0].Y.cpu(), arrays.force_columns, PLACE)
        X = [torch.from_numpy(arrays.pressure[p.rows]) for _, _, p in jobs]
        Y = [torch.from_numpy(arrays.targets[p.rows]) for _, _, p in jobs]
        plain = response.fit_codes(fit, X, Y, [p.n_effective for _, _, p in jobs], recipe, seed)
        STATE["cells"], STATE["kish"] = cells, []
        try:
            codes = response.fit_codes(fit, X, Y, [p.n_effective for _, _, p in jobs], recipe, seed)
        finally:
            STATE["cells"] = None
        kish = np.array(STATE["kish"])
        print(f"weighted codes ({CELLS}): {cells.n_cells} cells, Kish fraction median {np.median(kish):.2f} "
              f"[{kish.min():.2f}, {kish.max():.2f}]; codes moved "
              f"{float((codes - plain).norm() / plain.norm()):.3f} of their norm", flush=True)
    return planned(ctx, arrays, sd, fit, carry, recipe, jobs, seed, codes, extra)


CELLS = sys.argv.pop(1)
if CELLS not in ("f", "fp"):
    raise SystemExit(f"CELLS {CELLS!r}: expected f or fp")
PLACE = CELLS == "fp"
plain_problem = response._plan_problem
response._plan_problem = weighted_problem
planned = pipe.calibrated
pipe.calibrated = with_weights
sys.argv[0] = "scripts/rescore_response.py"
runpy.run_path("scripts/rescore_response.py", run_name="__main__")
