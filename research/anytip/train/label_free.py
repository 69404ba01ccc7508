"""A new unit's response-transfer codes without labels, from the pressures of its ordinary use
(research log entries 27, 35, 37-40 and 44).

Without labels each unlabeled row's contact is unknown too, so the codes z (C, k) and every
row's standardised contact c_i (D,) are fitted together: the MAP of

    sum_i w |x_i - G(c_i; z)|^2_W / 2 + w lam |c_i - c0_i|^2 / 2 + |z - z0|^2_P / 2

(W the training units' residual precision per barometer, w = n_eff / n, c0_i a start network's
contact, lam a weak pull towards it that keeps a contact no barometer feels determined) by
Levenberg-Marquardt on the codes' Schur complement, each row's contact eliminated, as bundle
adjustment solves cameras and points (`joint_fit`).

A unit's sensitivity and the force it is pressed with scale its pressures alike, so the fit alone
finds where and in which direction a unit is pressed but not how hard (entry 38). `ForceScale` adds
what the fleet knows of how hard: the mean square contact force m(c) of the rows, which the training
units' ordinary use puts at m0 with a spread s^2 over units, enters as (m(c) - m0)^2 / (2 s^2). It
couples every row's contact through one number, a rank-one term the elimination takes by
Sherman-Morrison (entry 39). Alone it cannot pull back a fit the search left at the wrong scale;
held to it in every search round too, the fit presses units about as hard as they are (entry 40).

The objective has many basins: started at codes zero and the start network's contacts the fit
stops far from the truth, started at the truth it stays there (entry 37). `searched_start` finds
a start without labels: each row's contact becomes the training units' labeled contact whose
response under the current codes lies nearest its pressures, and the codes are fitted to those
contacts, in turn (entry 38). From codes zero the search still ends in a worse basin than from the
codes the fleet's code encoder predicts from the unit's pressure statistics
(`fleet_code_encoder`), where it starts by default (entry 44).

Shapes: n unlabeled rows, C barometers, D label columns, k code_dim, S candidate contacts.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, fields
from typing import Any, Literal

import numpy as np
import torch
from torch import Tensor

from anytip.data.arrays import FleetArrays
from anytip.data.calibration import calibration_stream
from anytip.data.plans import stream_ordinary_use
from anytip.data.seeds import unit_seed
from anytip.models.io import LoadedModels
from anytip.train.code_encoder import CodeEncoder, stream_features
from anytip.train.fleet import FitResult
from anytip.train.metrics import predict
from anytip.train.response import (
    ResponseFit,
    ResponseRecipe,
    evenly_spaced,
    fit_codes,
    respond,
)

DISTIL = ("none", "fitted", "oracle")
OPTIONAL = ("plan_rows", "plan_iterations")  # counts that may be None
WITH_USE = "response+use"  # a labeled budget's method with the unit's ordinary use
# the joint fit at one point: pressures of the unlabeled and labeled rows, and their Jacobians when asked
Point = tuple[Tensor, Tensor | None, Callable[[], tuple[Tensor, Tensor, Tensor | None]]]


@dataclass(frozen=True)
class LabelFreeRecipe:
    """How a unit's codes are fitted from its unlabeled rows: at most `rows` evenly spaced rows of
    `seconds` of contact, worth `seconds * effective_hz` independent rows; the pull's weight;
    `candidates` labeled contacts searched in `rounds` alternations; `iterations` joint steps;
    `force_scale`: hold the search and the fit to the fleet's force scale (`ForceScale`, entry 40);
    `start`: the search's first codes, the fleet's code encoder's for the unit (`fleet_code_encoder`,
    entry 44) or zero (the fleet's typical unit); `plan_rows`: at most this many of a plan's labeled
    rows, evenly spaced, enter a joint fit with them (`plan_and_use_codes`; None: all of them, entry
    45), as `fit_codes` reads `code_rows` of them (entry 46); `distil`: with a plan, the unlabeled rows
    join the unit's network's rows `distil_repeat` times, labeled with the joint fit's contacts
    (`fitted`), with their true contacts (`oracle`, a research ceiling: ordinary use has none), or
    not at all (`none`; entry 78); `plan_iterations`: the joint fit's steps with a plan's labeled rows
    (None: `iterations`, as runs before entry 81 recorded it; 10 lose nothing to 30, entry 81);
    `use_weight`: in a joint fit with a plan's labeled rows, the unlabeled rows weigh this times their
    independent rows (the fit follows the ratio of the two weights, not their scale, entry 187);
    `search_draw`: which random draw of the training units' labeled contacts the search reads (0, the
    default, the one every run before entry 219 read; others show how far the fit's basin follows the
    draw); `starts`: the label-free fit runs from that many draws in turn (`search_draw` on) and the
    unit takes the mean of their codes (entry 220); `final_scale`: after the joint fit, its contacts'
    forces are scaled to the force-scale prior's mean square and the codes refitted to them
    (`rescaled_codes`, entry 223: on by default since, false in a recipe recorded before), as each
    search round does before it; a joint fit with a plan's labeled rows is left as it ends (their
    labels carry the scale)."""

    seconds: float = 600.0
    rows: int = 4096
    pull: float = 0.001
    candidates: int = 16384
    rounds: int = 5
    iterations: int = 30
    force_scale: bool = True
    start: Literal["encoder", "zero"] = "encoder"
    plan_rows: int | None = 2048
    distil: Literal["none", "fitted", "oracle"] = "none"
    distil_repeat: int = 1
    plan_iterations: int | None = 10
    use_weight: float = 1.0
    search_draw: int = 0
    starts: int = 1
    final_scale: bool = True

    def __post_init__(self) -> None:
        counts = {"rows": 1, "candidates": 1, "rounds": 0, "iterations": 1, "plan_rows": 1,
                  "distil_repeat": 1, "plan_iterations": 1, "search_draw": 0, "starts": 1}
        for key, least in counts.items():
            v = getattr(self, key)
            if not (v is None and key in OPTIONAL) and (type(v) is not int or v < least):
                raise ValueError(f"{key}: expected a whole number >= {least}, got {v!r}")
        for key, most in (("seconds", 600.0), ("pull", math.inf), ("use_weight", 1e6)):
            v = getattr(self, key)
            if type(v) not in (int, float) or not 0 < v <= most:
                raise ValueError(f"{key}: expected a number in (0, {most:g}], got {v!r}")
        for key in ("force_scale", "final_scale"):
            if type(getattr(self, key)) is not bool:
                raise ValueError(f"{key}: expected true or false, got {getattr(self, key)!r}")
        if self.start not in ("encoder", "zero"):
            raise ValueError(f"start: expected 'encoder' or 'zero', got {self.start!r}")
        if self.distil not in DISTIL:
            raise ValueError(f"distil: expected one of {', '.join(DISTIL)}, got {self.distil!r}")

    def steps_with_plan(self) -> int:
        """The joint fit's steps with a plan's labeled rows (`plan_iterations`, else `iterations`)."""
        return self.iterations if self.plan_iterations is None else self.plan_iterations

    def read_rows(self, n: int) -> np.ndarray:
        """Indices of the rows a fit reads of n rows of ordinary use: at most `rows`, evenly spaced."""
        return evenly_spaced(n, self.rows).numpy()

    @classmethod
    def from_json(cls, values: Any) -> LabelFreeRecipe:
        """A recipe from JSON values (`asdict`'s); ValueError naming an unknown or bad key."""
        if not isinstance(values, dict):
            raise ValueError(f"expected a mapping, got {type(values).__name__}")
        unknown = set(values) - {f.name for f in fields(cls)}
        if unknown:
            raise ValueError(f"unknown keys {sorted(unknown)}")
        # recorded before entry 81: `iterations` steps; before entry 223: the fit's contacts as they end
        return cls(**{"plan_iterations": None, "final_scale": False, **values})


@dataclass(frozen=True)
class ForceScale:
    """The fleet's prior on how hard a unit is pressed in ordinary use: the rows' mean square contact
    force (N^2, over the label columns `columns`, the force components) is `mean`, with variance `var`
    (N^4) over units."""

    columns: tuple[int, ...]
    mean: float
    var: float

    @classmethod
    def from_units(cls, labels: list[Tensor], columns: tuple[int, ...]) -> ForceScale:
        """From the labels (n_u, D) of each training unit's ordinary use: their mean square forces'
        mean and variance over units (at least two units)."""
        if len(labels) < 2:
            raise ValueError(f"a force-scale prior needs at least two units' ordinary use, got {len(labels)}")
        m = torch.tensor([mean_square_force(y, columns) for y in labels], dtype=torch.float64)
        if not m.var() > 0:
            raise ValueError(f"the {len(labels)} units' ordinary use presses every one equally hard "
                             f"({float(m[0]):.6g} N^2 mean square): a force-scale prior needs a spread")
        return cls(tuple(columns), float(m.mean()), float(m.var()))

    @classmethod
    def from_json(cls, values: Any, n_labels: int) -> ForceScale:
        """`asdict`'s values read back for contacts of `n_labels` columns; ValueError naming the key
        where one is missing or bad."""
        if not isinstance(values, dict):
            raise ValueError(f"expected a mapping, got {type(values).__name__}")
        columns = values.get("columns")
        if (not isinstance(columns, list) or not columns
                or any(type(c) is not int or not 0 <= c < n_labels for c in columns)):
            raise ValueError(f"columns: expected label columns in [0, {n_labels}), got {columns!r}")
        mean, var = values.get("mean"), values.get("var")
        for key, v in (("mean", mean), ("var", var)):
            if type(v) not in (int, float) or not math.isfinite(v) or v <= 0:
                raise ValueError(f"{key}: expected a positive number, got {v!r}")
        return cls(tuple(columns), float(mean), float(var))  # type: ignore[arg-type]

    def penalty(self, Y: Tensor) -> float:
        """(m(Y) - mean)^2 / (2 var) for physical contacts Y (n, D)."""
        return (mean_square_force(Y, self.columns) - self.mean) ** 2 / (2 * self.var)

    def match(self, Y: Tensor) -> Tensor:
        """Physical contacts Y (n, D) with their forces scaled by one factor so that their mean square
        is the prior's `mean` (directions, and every other column, kept)."""
        m = mean_square_force(Y, self.columns)
        out = Y.clone()
        if m > 0:
            out[:, list(self.columns)] *= (self.mean / m) ** 0.5
        return out


@dataclass(frozen=True)
class FleetUse:
    """What a benchmark learnt for reading a new unit's ordinary use, saved with its response model
    (metadata key `label_free`) so `anytip calibrate` reads a unit as the benchmark did: the recipe,
    the rows per second of contact worth one independent row (`effective_hz`), the force-scale prior
    and the code encoder (None where the run had none)."""

    free: LabelFreeRecipe
    effective_hz: float
    scale: ForceScale | None
    coder: CodeEncoder | None

    def n_effective(self) -> float:
        """Independent rows of the recipe's seconds of ordinary use."""
        return self.free.seconds * self.effective_hz

    def to_json(self) -> dict[str, Any]:
        """JSON values (`from_json`)."""
        return {"recipe": asdict(self.free), "effective_hz": self.effective_hz,
                "force_scale": None if self.scale is None else {**asdict(self.scale),
                                                                 "columns": list(self.scale.columns)},
                "encoder": None if self.coder is None else self.coder.to_json()}

    @classmethod
    def from_json(cls, values: Any, n_labels: int) -> FleetUse:
        """`to_json`'s values read back for contacts of `n_labels` columns; ValueError naming the key
        and the bad entry (`recipe: rows: ...`, `encoder: weights: ...`) where one is missing or bad."""
        if not isinstance(values, dict):
            raise ValueError(f"expected a mapping, got {type(values).__name__}")
        hz = values.get("effective_hz")
        if type(hz) not in (int, float) or not math.isfinite(hz) or hz <= 0:
            raise ValueError(f"effective_hz: expected a positive number, got {hz!r}")
        parts: dict[str, Any] = {}
        for key, read in (("recipe", LabelFreeRecipe.from_json),
                          ("force_scale", lambda v: ForceScale.from_json(v, n_labels)),
                          ("encoder", CodeEncoder.from_json)):
            try:
                parts[key] = None if values.get(key) is None and key != "recipe" else read(values.get(key))
            except ValueError as e:
                raise ValueError(f"{key}: {e}") from None
        return cls(parts["recipe"], float(hz), parts["force_scale"], parts["encoder"])


def fleet_force_scale(arrays: FleetArrays, units: list[str], protocol: str | None, interleave: bool,
                      free: LabelFreeRecipe, seed: int) -> ForceScale | None:
    """The force-scale prior of the training units `units`: each one's ordinary use read as a new
    unit's is (`free.seconds` of whole presses drawn from its calibration stream, `free.rows` evenly
    spaced rows), its labels kept. None where the sensor model has no force target; a unit without
    presses gives none."""
    columns = tuple(arrays.force_columns)
    if not columns:
        return None
    labels = []
    for u in units:
        rows = ordinary_rows(arrays, u, protocol, interleave, free.seconds, seed)
        if len(rows):
            labels.append(torch.from_numpy(arrays.targets[rows[free.read_rows(len(rows))]]))
    return ForceScale.from_units(labels, columns)


def ordinary_rows(arrays: FleetArrays, unit: str, protocol: str | None, interleave: bool, seconds: float,
                  seed: int) -> np.ndarray:
    """A training unit's ordinary use read as a new unit's: the rows of `seconds` of whole presses drawn
    from its calibration stream (`anytip.data.plans.stream_ordinary_use`)."""
    stream = calibration_stream(arrays, unit, protocol, interleave=interleave)
    return stream_ordinary_use(arrays, unit, stream, seconds, seed).rows


def use_inputs(P: np.ndarray, free: LabelFreeRecipe, start: FitResult | LoadedModels,
               coder: CodeEncoder | None, device: torch.device | str) -> tuple[Tensor, Tensor, Tensor | None]:
    """What a fit reads of a unit's ordinary use, its pressures P (n, C) Pa: at most `free.rows` of its
    rows, evenly spaced, X (m, C) Pa; the start network's contacts there Y0 (m, D), which the fit pulls
    each row towards; and the encoder's first codes (C, k) from the statistics of all of P (None
    without an encoder or with fewer than two rows). All on `device`."""
    X = torch.from_numpy(P[free.read_rows(len(P))])
    Y0 = predict(start.model, start.in_scaler, start.out_scaler, X[None].to(start.in_scaler.mean.device))[0]
    return X.to(device), Y0.to(device), encoder_codes(P, coder, device)


def encoder_codes(P: np.ndarray, coder: CodeEncoder | None, device: torch.device | str) -> Tensor | None:
    """(C, k) on `device`: the codes `coder` predicts from the statistics of a unit's ordinary use,
    its pressures P (n, C) Pa; None without an encoder or with fewer than two rows. A ValueError
    where the encoder's features do not fit P's."""
    return coder(stream_features(P)).to(device) if coder is not None and len(P) > 1 else None


def fleet_code_encoder(fit: ResponseFit, sources: list[FleetArrays], protocol: str | None, interleave: bool,
                       seconds: float, seed: int) -> CodeEncoder | None:
    """The code encoder learnt on every unit of the response model `fit` whose stream one of `sources`
    holds (the registry's training units, and its extra units where the model learnt them): each one's
    `stream_features` of its ordinary use (`ordinary_rows`) against its codes. None where fewer than
    three such units have ordinary use, or where the left-out units' codes are explained no better
    than by the units' mean (loo_r2 <= 0): the search then starts from the code prior's mean."""
    feats, index = [], []
    for i, u in enumerate(fit.unit_ids):
        arrays = next((a for a in sources if u in a.units), None)
        if arrays is None:
            continue
        rows = ordinary_rows(arrays, u, protocol, interleave, seconds, seed)
        if len(rows) > 1:
            feats.append(stream_features(arrays.pressure[rows]))
            index.append(i)
    if len(index) < 3:
        return None
    codes = fit.model.codes.detach().cpu().numpy()[index]
    coder = CodeEncoder.fit(np.stack(feats), codes, fit.code_var.cpu().numpy())
    return coder if coder.loo_r2 > 0 else None


def mean_square_force(Y: Tensor, columns: tuple[int, ...]) -> float:
    """The mean over rows of the squared norm of contacts Y (n, D)'s force columns, N^2."""
    return float(Y[:, list(columns)].pow(2).sum(-1).mean())


@dataclass(frozen=True)
class Labeled:
    """Labeled rows fitted beside the unlabeled ones: pressures X (m, C) Pa, contacts Y (m, D)
    physical, worth n_eff independent rows (a calibration plan's, entry 45)."""

    X: Tensor
    Y: Tensor
    n_eff: float

    def data_term(self, fit: ResponseFit, pressures: Tensor) -> float:
        """n_eff / m times half the rows' sum of squared residuals over noise_var, the response to
        the rows' contacts being `pressures` (m, C) Pa."""
        r = self.X - pressures
        return float((r**2 * (self.n_eff / len(self.X) / fit.noise_var)).sum() / 2)

    def thinned(self, at_most: int | None) -> Labeled:
        """At most `at_most` of the rows, evenly spaced, still worth n_eff (all of them for None)."""
        if at_most is None:
            return self
        take = evenly_spaced(len(self.X), at_most).to(self.X.device)
        return Labeled(self.X[take], self.Y[take], self.n_eff)


def joint_objective(fit: ResponseFit, X: Tensor, c0: Tensor, w: float, c: Tensor, codes: Tensor,
                    lam: float, scale: ForceScale | None = None, labeled: Labeled | None = None) -> float:
    """The joint MAP's objective (module docstring) of unlabeled pressures X (n, C) Pa at standardised
    contacts c (n, D) and codes (C, k), with the pull towards standardised contacts c0 (n, D),
    each row weighing w = n_eff / n, the force-scale prior and the labeled rows' data term where
    given."""
    model = fit.model
    with torch.no_grad():
        pred = model(c * model.label_std + model.label_mean, codes)
        known = None if labeled is None else model(labeled.Y, codes)
    return objective_at(fit, X, c0, w, c, codes, lam, pred, scale, labeled, known)


def objective_at(fit: ResponseFit, X: Tensor, c0: Tensor, w: float, c: Tensor, codes: Tensor, lam: float,
                 pred: Tensor, scale: ForceScale | None = None, labeled: Labeled | None = None,
                 known: Tensor | None = None) -> float:
    """`joint_objective` given the response at the point: `pred` (n, C) Pa to the unlabeled rows'
    contacts c, `known` (m, C) Pa to the labeled rows' contacts (with `labeled`), both at `codes`."""
    model = fit.model
    Y = c * model.label_std + model.label_mean
    r = X - pred
    data, pull = (r**2 * (w / fit.noise_var)).sum() / 2, w * lam * ((c - c0) ** 2).sum() / 2
    prior = 0.0 if scale is None else scale.penalty(Y)
    term = 0.0 if labeled is None else labeled.data_term(fit, known)  # known: given with labeled
    return float(data + pull + fit.code_prior.penalty(codes).sum()) + prior + term


def scale_residual(scale: ForceScale, c: Tensor, mean: Tensor, std: Tensor) -> tuple[float, Tensor]:
    """The force-scale prior as one weighted residual e = (m - m0) / s at standardised contacts c (n, D)
    and its gradient u = de/dc (n, D), so that the prior is e^2 / 2 and its Gauss-Newton Hessian u u^T."""
    Y, cols = c * std + mean, list(scale.columns)
    s = scale.var**0.5
    u = torch.zeros_like(c)
    u[:, cols] = 2 * Y[:, cols] * std[cols] / (len(c) * s)
    return (mean_square_force(Y, scale.columns) - scale.mean) / s, u


def joint_fit(fit: ResponseFit, X: Tensor, Y0: Tensor, n_eff: float, iterations: int, lam: float,
              start: tuple[Tensor, Tensor] | None = None, scale: ForceScale | None = None,
              labeled: Labeled | None = None) -> tuple[Tensor, Tensor, list[float]]:
    """Codes (C, k) and contacts (n, D) of unlabeled pressures X (n, C) Pa, pulled towards contacts
    Y0 (n, D), by damped Gauss-Newton on the joint MAP (module docstring), with the force-scale prior
    `scale` and `labeled` rows (their contacts known, so they enter the codes' block alone) where
    given; the objective after each step. The fit starts at the code prior's mean and contacts Y0,
    or at `start` (codes (C, k), contacts (n, D) physical). The response model's weights are frozen
    (left without grad)."""
    model = fit.model
    for p in model.parameters():
        p.requires_grad_(False)
    mean, std = model.label_mean, model.label_std
    (n, C), k, D = X.shape, fit.code_var.shape[0], Y0.shape[1]
    w = n_eff / n
    Wc, code_prior = w / fit.noise_var, fit.code_prior
    c0 = (Y0 - mean) / std
    if start is None:
        c, z = c0.clone(), code_prior.mean.clone()
    else:
        c, z = (start[1] - mean) / std, start[0].clone()

    def linearised(cc: Tensor, zz: Tensor) -> tuple[float, Point]:
        """The objective at (cc, zz) and what a step from there needs: the unlabeled and the labeled
        rows' pressures, and a call for their Jacobians in the standardised contacts and the codes
        (one backward pass each through the same forward passes, taken once, when a step starts
        there: a refused trial costs its forward passes alone)."""
        pred, unlabeled = model.linearisation(cc * std + mean, zz)
        known, known_d = model.linearisation(labeled.Y, zz) if labeled is not None else (None, None)

        @functools.cache
        def derivatives() -> tuple[Tensor, Tensor, Tensor | None]:
            Jy, Jz = unlabeled()
            return Jy * std, Jz, None if known_d is None else known_d()[1]

        obj = objective_at(fit, X, c0, w, cc, zz, lam, pred, scale, labeled, known)
        return obj, (pred, known, derivatives)

    (obj, at), damping, trace = linearised(c, z), 1e-2, []
    for _ in range(iterations):
        pred, known, derivatives = at
        Jc, Jz, Jk = derivatives()
        r = X - pred
        Hcc = torch.einsum("ncd,nce,c->nde", Jc, Jc, Wc) + w * lam * torch.eye(D, device=X.device)
        gc = torch.einsum("ncd,nc,c->nd", Jc, r, Wc) - w * lam * (c - c0)
        Hzz = torch.einsum("nck,ncj,c->ckj", Jz, Jz, Wc) + code_prior.precision
        gz = torch.einsum("nck,nc,c->ck", Jz, r, Wc) + code_prior.pull(z)
        if labeled is not None and Jk is not None:
            Wk = labeled.n_eff / len(labeled.X) / fit.noise_var
            Hzz = Hzz + torch.einsum("nck,ncj,c->ckj", Jk, Jk, Wk)
            gz = gz + torch.einsum("nck,nc,c->ck", Jk, labeled.X - known, Wk)
        A = torch.einsum("nck,ncd,c->nckd", Jz, Jc, Wc).reshape(n, C * k, D)  # codes-contact coupling
        Hzz = Hzz + damping * torch.diag_embed(torch.diagonal(Hzz, dim1=-2, dim2=-1))
        Hcc = Hcc + damping * torch.diag_embed(torch.diagonal(Hcc, dim1=-2, dim2=-1))
        u = None
        if scale is not None:
            e, u = scale_residual(scale, c, mean, std)
            gc = gc - e * u
        dz, dc = schur_step(Hzz, gz.reshape(-1), Hcc, gc, A, u)
        trial, trial_at = linearised(c + dc, z + dz.reshape(C, k))
        if trial < obj:
            c, z, obj, at, damping = c + dc, z + dz.reshape(C, k), trial, trial_at, max(damping / 3, 1e-6)
        else:
            damping = min(damping * 4, 1e6)
        trace.append(obj)
    return z, c * std + mean, trace


def schur_step(Hzz: Tensor, gz: Tensor, Hcc: Tensor, gc: Tensor, A: Tensor, u: Tensor | None = None
               ) -> tuple[Tensor, Tensor]:
    """The Gauss-Newton step (dz (C * k,), dc (n, D)) of the system

        [[blockdiag(Hzz), B], [B^T, blockdiag(Hcc) + u u^T]] [dz, dc] = [gz, gc],  B = [A_1 ... A_n]

    with Hzz (C, k, k) each barometer's code block, Hcc (n, D, D) each row's contact block, A
    (n, C * k, D) the codes' coupling to each row's contact and u (n, D) a rank-one term over every
    contact (the force-scale prior), by eliminating the contacts (Schur complement on the codes; the
    rank-one term by Sherman-Morrison)."""
    Hinv = torch.linalg.inv(Hcc)
    AH = A @ Hinv
    S = torch.block_diag(*Hzz) - torch.einsum("nad,nbd->ab", AH, A)
    rhs = gz - torch.einsum("nad,nd->a", AH, gc)
    if u is not None:
        v = torch.einsum("nde,ne->nd", Hinv, u)
        beta, a = 1 + (u * v).sum(), torch.einsum("nad,nd->a", A, v)
        S, rhs = S + torch.outer(a, a) / beta, rhs + a * (v * gc).sum() / beta
    dz = torch.linalg.solve(S, rhs)
    dc = torch.einsum("nde,ne->nd", Hinv, gc - torch.einsum("nad,a->nd", A, dz))
    return dz, dc if u is None else dc - v * (u * dc).sum() / beta


def nearest_contacts(fit: ResponseFit, X: Tensor, candidates: Tensor, codes: Tensor,
                     chunk: int = 1024) -> Tensor:
    """For each row of pressures X (n, C) Pa, the candidate contact (of `candidates` (S, D), physical)
    whose response under `codes` (C, k) lies nearest, each barometer weighed by 1 / noise_var: (n, D)."""
    scale = fit.noise_var.sqrt()
    with torch.no_grad():
        P = respond(fit.model, candidates, codes) / scale
        best = [torch.cdist(X[a : a + chunk] / scale, P).argmin(1) for a in range(0, len(X), chunk)]
    return candidates[torch.cat(best)]


def search_candidates(labels: Tensor, n: int, seed: int, draw: int = 0) -> Tensor:
    """The contacts a search draws from: `n` of the training units' labeled rows `labels` (S, D),
    in a random order seeded by the run's `seed` (all of them where there are fewer); `draw` > 0 takes
    another order of the same seed (`LabelFreeRecipe.search_draw`)."""
    g = torch.Generator().manual_seed(seed if draw == 0 else unit_seed(seed, draw, "label-free search draw"))
    return labels[torch.randperm(len(labels), generator=g)[:n].to(labels.device)]


def search_draws(labels: Tensor, free: LabelFreeRecipe, seed: int) -> list[Tensor]:
    """The candidates (S, D) of each of the recipe's `starts` draws, from `search_draw` on
    (`search_candidates`); the first is the one a joint fit with a plan's rows reads."""
    first = free.search_draw
    return [search_candidates(labels, free.candidates, seed, first + i) for i in range(free.starts)]


def searched_start(fit: ResponseFit, recipe: ResponseRecipe, X: Tensor, n_eff: float, candidates: Tensor,
                   seed: int, rounds: int, scale: ForceScale | None = None, codes: Tensor | None = None
                   ) -> tuple[Tensor, Tensor]:
    """Codes (C, k) and contacts (n, D) of unlabeled pressures X (n, C) Pa without a start network:
    from `codes` (default the code prior's mean, the fleet's typical unit), `rounds` times each row's nearest
    candidate contact (`nearest_contacts`), then the codes' MAP given those contacts (`fit_codes`, as
    if they were labels). With `scale`, the contacts' forces are scaled to the prior's mean square
    each round before the codes are fitted (`ForceScale.match`), so the search cannot trade
    sensitivity for force (entry 40)."""
    if codes is None:
        codes = fit.code_prior.mean.clone()

    def nearest() -> Tensor:
        found = nearest_contacts(fit, X, candidates, codes)
        return found if scale is None else scale.match(found)

    for _ in range(rounds):
        codes = fit_codes(fit, [X], [nearest()], [n_eff], recipe, seed)[0]
    return codes, nearest()


def rescaled_codes(fit: ResponseFit, recipe: ResponseRecipe, X: Tensor, n_eff: float, contacts: Tensor,
                   scale: ForceScale, seed: int) -> tuple[Tensor, Tensor]:
    """The codes' MAP (C, k) given the contacts (n, D) physical of unlabeled pressures X (n, C) Pa with
    their forces scaled to the prior's mean square (`ForceScale.match`), and those contacts: a joint fit
    ends below the prior's force scale by a few percent, and the further a unit's fit ends from its
    true scale the larger its force error (entries 222-223)."""
    matched = scale.match(contacts)
    return fit_codes(fit, [X], [matched], [n_eff], recipe, seed)[0], matched


def label_free_codes(fit: ResponseFit, recipe: ResponseRecipe, free: LabelFreeRecipe, X: Tensor, Y0: Tensor,
                     n_eff: float, candidates: Tensor, seed: int, scale: ForceScale | None = None,
                     codes: Tensor | None = None) -> tuple[Tensor, Tensor, list[float]]:
    """A new unit's codes (C, k) from its unlabeled pressures X (n, C) Pa: the joint fit from the
    searched start (its search from `codes`, default the code prior's mean), pulled towards a start
    network's contacts Y0 (n, D), with the force-scale prior `scale` where given; its contacts (n, D)
    and its objective after each step. Without rows the codes stay at the prior's mean (the fleet's
    typical unit), as `fit_codes` leaves a job without rows. With `free.final_scale` and a prior, the
    codes and contacts are `rescaled_codes`' from the fit's contacts (the objective still the fit's)."""
    if not len(X):
        return fit.code_prior.mean.clone(), Y0, []
    start = searched_start(fit, recipe, X, n_eff, candidates, seed, free.rounds, scale, codes)
    z, c, trace = joint_fit(fit, X, Y0, n_eff, free.iterations, free.pull, start, scale)
    if free.final_scale and scale is not None:
        z, c = rescaled_codes(fit, recipe, X, n_eff, c, scale, seed)
    return z, c, trace


def started_codes(fit: ResponseFit, recipe: ResponseRecipe, free: LabelFreeRecipe, X: Tensor, Y0: Tensor,
                  n_eff: float, draws: list[Tensor], seed: int, scale: ForceScale | None = None,
                  codes: Tensor | None = None) -> tuple[Tensor, Tensor, list[float]]:
    """`label_free_codes` from each draw of candidates in `draws` (`search_draws`): the mean of their
    codes (C, k), the first draw's contacts (n, D), and each draw's final objective (none without
    rows). Entry 219: the draws end several percent apart per unit, and the lowest objective does
    not tell the better one."""
    fits = [label_free_codes(fit, recipe, free, X, Y0, n_eff, c, seed, scale, codes) for c in draws]
    finals = [trace[-1] for _, _, trace in fits if trace]
    return torch.stack([z for z, _, _ in fits]).mean(0), fits[0][1], finals


def plan_and_use_codes(fit: ResponseFit, recipe: ResponseRecipe, free: LabelFreeRecipe, X: Tensor, Y0: Tensor,
                       n_eff: float, candidates: Tensor, seed: int, labeled: Labeled, codes: Tensor,
                       scale: ForceScale | None = None) -> tuple[Tensor, Tensor]:
    """A unit's codes (C, k) from its plan's labeled rows and its ordinary use's unlabeled pressures
    X (n, C) Pa together (entry 45), and the unlabeled rows' fitted contacts (n, D) physical: each
    unlabeled row's first contact is its nearest candidate under the plan's own codes `codes` (C, k),
    scaled to the force prior where given, then `free.steps_with_plan()` steps of the joint fit with
    at most `free.plan_rows` of the labeled rows (entry 46), pulled towards contacts Y0 (n, D), the
    unlabeled rows worth `n_eff` times `free.use_weight`. Without unlabeled rows: `codes`."""
    if not len(X):
        return codes, Y0
    n_eff = n_eff * free.use_weight
    start = searched_start(fit, recipe, X, n_eff, candidates, seed, 0, scale, codes)
    z, c, _ = joint_fit(fit, X, Y0, n_eff, free.steps_with_plan(), free.pull, start, scale,
                        labeled.thinned(free.plan_rows))
    return z, c


def unit_codes_with_use(fit: ResponseFit, recipe: ResponseRecipe, fleet: FleetUse, X: Tensor, Y0: Tensor,
                        draws: list[Tensor], seed: int, plan: Labeled | None = None,
                        first: Tensor | None = None) -> tuple[Tensor, Tensor]:
    """One new unit's codes (C, k) from its ordinary use's pressures X (n, C) Pa, each row's contact
    pulled towards Y0 (n, D), read as `fleet` says: with a plan's labeled rows, their joint fit
    started from the plan's own codes (`plan_and_use_codes`, entries 45-46); without (or with an empty
    plan), the label-free fit searched from `first` (C, k) from each draw of candidates in `draws`
    (`started_codes`, entries 44 and 220; a plan's joint fit reads the first). Also the rows' fitted
    contacts (n, D) physical."""
    n_eff = fleet.n_effective()
    if plan is not None and len(plan.X):
        codes = fit_codes(fit, [plan.X], [plan.Y], [plan.n_eff], recipe, seed)[0]
        return plan_and_use_codes(fit, recipe, fleet.free, X, Y0, n_eff, draws[0], seed, plan, codes,
                                  fleet.scale)
    z, c, _ = started_codes(fit, recipe, fleet.free, X, Y0, n_eff, draws, seed, fleet.scale, first)
    return z, c


def with_use_method(free: LabelFreeRecipe) -> str:
    """The method of a labeled budget calibrated with the unit's ordinary use: `response+use`, with
    `+distil` or `+oracle` where the use's rows join the unit's network (`free.distil`, entry 78)."""
    return {"none": WITH_USE, "fitted": f"{WITH_USE}+distil", "oracle": f"{WITH_USE}+oracle"}[free.distil]


def data_family(method: str) -> str:
    """The data a cross-sensor method's row was given: `with ordinary use` for the with-use methods
    (`with_use_method`), else `plan` (a labeled plan alone, or none at budget 0)."""
    return "with ordinary use" if method.startswith(WITH_USE) else "plan"


def distilled_rows(free: LabelFreeRecipe, X: Tensor, fitted: Tensor, truth: Tensor | None = None
                   ) -> tuple[Tensor, Tensor] | None:
    """What a unit's ordinary use adds to its network's rows under `free.distil` (entry 78): its
    unlabeled pressures X (n, C) Pa, `free.distil_repeat` times, with the joint fit's contacts
    `fitted` (n, D) or, for `oracle`, their true contacts `truth` (n, D); None for `none`."""
    if free.distil == "none":
        return None
    labels = fitted if free.distil == "fitted" else truth
    if labels is None:
        raise ValueError("distil: oracle needs the ordinary use's true contacts, which only a benchmark has")
    r = free.distil_repeat
    return X.repeat(r, 1), labels.to(X.dtype).repeat(r, 1)
