"""Research log entry 95: `scripts/rescore_response.py` with every plan-calibrated job's codes fitted as if
each press carried its own offset per barometer (a random effect of variance tau_c^2, integrated out):
generalised least squares, in which a press's mean residual weighs 1 / (tau_c^2 + its rows' noise over
their count) and the residuals about it weigh what a row does today. tau_c^2 is learnt from the registry's
training units: the variance of their presses' mean residuals about the response with their own codes,
less what independent rows would give. The unit's network then trains as `response@` does, on those codes
(with ordinary use the codes come from the joint fit, unchanged). Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry94/press_offsets.py RUN --registry REG --out OUT \\
        [rescore_response.py's options]
"""

import runpy
import sys

import numpy as np
import torch

import anytip.pipelines.cross_sensor_response as pipe
from anytip.data.plans import find_presses
from anytip.train.response import code_jacobian, evenly_spaced, fit_codes, frozen, respond

PRESSES_PER_UNIT = 200  # of a training unit's presses, evenly spaced, where tau is learnt
ROWS_PER_PRESS = 32


def press_means(r: np.ndarray, press: np.ndarray, n_press: int) -> tuple[np.ndarray, np.ndarray]:
    """Residuals r (n, C) of rows in presses `press` (n,): each press's mean (P, C) and row count (P,)."""
    count = np.bincount(press, minlength=n_press).astype(float)
    means = np.zeros((n_press, r.shape[1]))
    np.add.at(means, press, r)
    return means / np.maximum(count, 1)[:, None], count


def offset_variance(fit, arrays, units: list[str]) -> torch.Tensor:
    """(C,) Pa^2: tau^2 of each barometer from the training `units` the response model knows."""
    between, within = [], []
    for u in units:
        if u not in fit.unit_ids:
            continue
        presses = find_presses(arrays, u)
        picks = evenly_spaced(len(presses), PRESSES_PER_UNIT).numpy()
        rows, press = [], []
        for j, p in enumerate(picks):
            mine = presses.rows[presses.start[p]:presses.start[p + 1]]
            take = mine[evenly_spaced(len(mine), ROWS_PER_PRESS).numpy()]
            rows.append(take)
            press.append(np.full(len(take), j))
        rows, press = np.concatenate(rows), np.concatenate(press)
        code = fit.model.codes.detach()[fit.unit_ids.index(u)]
        labels = torch.from_numpy(arrays.targets[rows])
        r = (torch.from_numpy(arrays.pressure[rows]) - respond(fit.model, labels, code)).numpy()
        means, count = press_means(r, press, len(picks))
        var = np.zeros_like(means)
        np.add.at(var, press, (r - means[press]) ** 2)
        var /= np.maximum(count - 1, 1)[:, None]
        between.append(means ** 2)
        within.append(var / np.maximum(count, 1)[:, None])
    tau2 = np.maximum(np.concatenate(between).mean(0) - np.concatenate(within).mean(0), 0.0)
    return torch.tensor(tau2, dtype=torch.float32)


def gls_codes(fit, X, Y, bounds, n_eff, tau2, start, recipe) -> torch.Tensor:
    """(C, k) codes of one job (X (n, C) Pa, Y (n, D), presses at `bounds`, worth n_eff rows) by damped
    Gauss-Newton on the press-offset likelihood, from `start` (C, k)."""
    take = evenly_spaced(len(X), recipe.code_rows)
    press = torch.from_numpy(np.searchsorted(bounds, take.numpy(), side="right") - 1)
    Xt, Yt = X[take], Y[take]
    n_press = int(press.max()) + 1
    n_p = torch.bincount(press, minlength=n_press).float()  # (P,)
    w = n_eff / len(take) / fit.noise_var  # (C,) per row
    omega = 1 / (tau2 + 1 / (w * n_p[:, None]).clamp_min(1e-12))  # (P, C)
    kappa = w * n_p[:, None] - omega  # (P, C)
    prior = fit.code_prior

    def mean_of(v: torch.Tensor) -> torch.Tensor:
        return torch.zeros(n_press, *v.shape[1:]).index_add_(0, press, v) / n_p.view(-1, *[1] * (v.dim() - 1))

    def loss(codes: torch.Tensor) -> torch.Tensor:
        r = Xt - respond(fit.model, Yt, codes)
        return (w * (r ** 2).sum(0) - (kappa * mean_of(r) ** 2).sum(0)) / 2 + prior.penalty(codes)

    codes, damping = start.clone(), torch.full((fit.model.n_channels,), 1e-2)
    current = loss(codes)
    for _ in range(recipe.code_iterations):
        pred, J = code_jacobian(fit.model, Yt, codes)  # (B, C), (B, C, k)
        r = Xt - pred
        Jm, rm = mean_of(J), mean_of(r)
        H = (torch.einsum("c,bck,bcj->ckj", w, J, J) - torch.einsum("pc,pck,pcj->ckj", kappa, Jm, Jm)
             + prior.precision)
        g = (torch.einsum("c,bck,bc->ck", w, J, r) - torch.einsum("pc,pck,pc->ck", kappa, Jm, rm)
             + prior.pull(codes))
        diag = torch.diagonal(H, dim1=-2, dim2=-1)
        step = torch.linalg.solve(H + torch.diag_embed(damping[:, None] * diag), g.unsqueeze(-1)).squeeze(-1)
        trial = loss(codes + step)
        kept = trial < current
        codes = torch.where(kept[:, None], codes + step, codes)
        current = torch.where(kept, trial, current)
        damping = torch.where(kept, damping / 3, damping * 4).clamp(1e-6, 1e6)
    return codes


def with_offsets(ctx, arrays, sd, fit, carry, recipe, jobs, seed, codes=None, extra=None):
    """`calibrated`, its jobs' codes (where not given) fitted under per-press offsets."""
    if codes is None:
        tau2 = offset_variance(fit, arrays, list(sd.split.train))
        X = [torch.from_numpy(arrays.pressure[p.rows]) for _, _, p in jobs]
        Y = [torch.from_numpy(arrays.targets[p.rows]) for _, _, p in jobs]
        n_eff = [p.n_effective for _, _, p in jobs]
        start = fit_codes(fit, X, Y, n_eff, recipe, seed)
        with frozen(fit.model):
            codes = torch.stack([gls_codes(fit, X[m], Y[m], jobs[m][2].bounds, n_eff[m], tau2, start[m],
                                           recipe) for m in range(len(jobs))])
        ratio = " ".join(f"{v:.2f}" for v in (tau2 / fit.noise_var).tolist())
        print(f"press offsets: tau^2 / noise {ratio}; "
              f"codes moved {float((codes - start).norm() / start.norm()):.3f} of their norm", flush=True)
    return planned(ctx, arrays, sd, fit, carry, recipe, jobs, seed, codes, extra)


planned = pipe.calibrated
pipe.calibrated = with_offsets
sys.argv[0] = "scripts/rescore_response.py"
runpy.run_path("scripts/rescore_response.py", run_name="__main__")
