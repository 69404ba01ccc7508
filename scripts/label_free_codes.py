"""A new unit's codes without labels: what its unlabeled stream tells response transfer (research
log entries 27, 30, 35, 37 and 38).

Zero-shot calibration may read a new unit's pressures in ordinary use (the first `--seconds` of its
stream, labels unread; with `--unlabeled spread`, `--seconds` of contact as random whole presses from
anywhere in the stream outside the unit's test patches, `anytip.data.plans.ordinary_use`, for the
new units and for every unit the encoders learn from: research log entry 35). Response transfer
needs the unit's codes. Without labels, each unlabeled row's contact is unknown too, so the codes
and every row's contact are fitted together (`anytip.train.label_free`: the joint MAP, with a pull
of weight `--pull` towards the start network's contacts).
Arms, each scored by a network trained on the transferred rows alone (no labeled row of the unit)
from the run's pooled start network:

- `pooled`: the start network itself (the training units' rows as measured): no transfer;
- `zero`: codes zero (the fleet's typical unit);
- `joint`: the label-free fit above;
- `joint_truth`: the same fit started at the truth (the `stream_labels` codes and the rows' true
  contacts) instead of at codes zero and the start network's contacts: where the objective leads
  from there separates an optimiser that stops short from an objective whose minimum lies away
  from the truth (research log entry 37);
- `joint_search`: the same fit started from a global search instead (`searched_start`): each row's
  contact is the training units' labeled row whose response under the current codes lies nearest
  its pressures, and the codes are fitted to those contacts, in turn, from codes zero (entry 38);
- `joint_scale`: `joint_search` with the fleet's prior on how hard a unit is pressed (`ForceScale`:
  the mean square contact force of the registry's training units' ordinary use, read as the new
  unit's is, its mean and spread over those units; entry 39);
- `joint_scale_start`: `joint_scale` whose searched start also scales its contacts' forces to the
  prior's mean square each round (`searched_start` with the prior; entry 40);
- `joint_scale_draws`: the mean of `--draws` `joint_scale_start` codes, each searched among another
  random draw of the training units' labeled contacts (entry 43);
- `joint_scale_encoder`: `joint_scale_start` whose search starts from the `encoder` arm's codes
  instead of codes zero (entry 44);
- `joint_scale_rescaled`: `joint_scale_encoder`'s fit with its contacts' forces scaled to the prior's
  mean square and the codes refitted to them (`rescaled_codes`, `LabelFreeRecipe.final_scale`; entry
  223); needs `joint_scale_encoder`;
- `stream_labels`: codes fitted on the same rows with their labels (no label-free method has them):
  the most those seconds of pressures could tell the codes;
- `plan`: codes fitted on the labeled rows of the run's plan of `--plan-seconds` robot-seconds (the
  run's own strategy), for comparison: the labeled method without the unit's rows in its network;
- `plan_joint`: the plan's labeled rows and the unlabeled rows in one joint fit
  (`plan_and_use_codes`), started from the `plan` codes, held to the force scale (entry 45), with at
  most `LabelFreeRecipe.plan_rows` of the plan's rows, evenly spaced (entry 46); `plan_joint_all`: the
  same with every row of the plan (as entry 45 ran it); each records its fit's seconds;
- `input_stats`: no codes; the run's shared model without adapters, scaled by the unit's unlabeled
  input statistics (the benchmark's zero-shot method; always the stream's first `--seconds`, as its
  shared model's training units were scaled);
- `encoder`: codes predicted from order-free statistics of the unlabeled stream (`stream_features`)
  by ridge regression learnt across the response model's units (`CodeEncoder`); `encoder_own`: learnt
  on the registry's own training units; `encoder_more`: also on the units of `--encoder-units`,
  whose codes the frozen response model fits from their whole streams;
- `all_labels`: codes fitted on the labels of the unit's whole stream (what a perfect encoder gives);
- `toward_all_<t>`: the encoder's codes moved a share t of the way to `all_labels`' (an encoder whose
  code error is 1 - t of this one's).

    python scripts/label_free_codes.py reports/cross_sensor_response_start/fleet24_seed1 \\
        --registry data/fleet24 --out reports/cross_sensor_label_free_codes/fleet24_seed1.json

Per unit and arm: the test-patch pressure residual about the arm's response (Pa) and, for held-out
units, the force and angle ratio to the run's reference; per unit, the joint objective's data term
per row at the joint fit and at the truth (stream_labels codes, true contacts), which separates
an optimiser that stops short (truth lower) from data that do not pin the codes down (fit lower).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
from torch import Tensor

from anytip.config import DataConfig, load_spec
from anytip.data.arrays import FleetArrays, load_arrays
from anytip.data.calibration import CalibrationStream, calibration_stream
from anytip.data.plans import Budget, Presses, ordinary_use, ordinary_use_seed, stream_ordinary_use
from anytip.data.registry import Registry
from anytip.errors import AnytipError
from anytip.models.io import LoadedModels, load_models, load_response, load_shared
from anytip.pipelines.common import Context, load, load_extra, select_runs
from anytip.pipelines.cross_sensor import SeedData, min_units, prepare
from anytip.pipelines.cross_sensor_jobs import plan_of
from anytip.pipelines.cross_sensor_options import Options, parse_options
from anytip.rundir import read_json
from anytip.train.adapt import calibrate_and_fold
from anytip.train.code_encoder import CodeEncoder, stream_features
from anytip.train.label_free import (
    ForceScale,
    Labeled,
    LabelFreeRecipe,
    fleet_force_scale,
    joint_fit,
    joint_objective,
    label_free_codes,
    mean_square_force,
    plan_and_use_codes,
    rescaled_codes,
    search_candidates,
    searched_start,
)
from anytip.train.metrics import ratio_fields, scores
from anytip.train.response import (
    ResponseFit,
    ResponseRecipe,
    SourceRows,
    evenly_spaced,
    fit_codes,
    residual_rms,
    source_rows,
    start_network_path,
    transfer,
    unit_networks,
)
from anytip.train.shared_split import predict_rows

SCALED = ("joint_scale", "joint_scale_start", "joint_scale_draws", "joint_scale_encoder",
          "joint_scale_rescaled", "plan_joint", "plan_joint_all")  # the arms with the force-scale prior
ARMS = ("pooled", "input_stats", "zero", "joint", "joint_truth", "joint_search", "joint_scale",
        "joint_scale_start", "joint_scale_draws", "joint_scale_encoder", "joint_scale_rescaled", "encoder",
        "encoder_own", "encoder_more", "stream_labels", "all_labels", "plan", "plan_joint", "plan_joint_all")
JOINT = ("joint", "joint_truth", "joint_search", *SCALED)  # the joint fit's arms
SEARCH = LabelFreeRecipe()  # the searched start's candidates and default rounds (the joint_search arms)
DRAWS = 3  # candidate draws the joint_scale_draws arm averages by default
TOWARD = "toward_all_"  # arm toward_all_<t>: the encoder's codes moved a share t of the way to all_labels'


def arm_names(text: str) -> tuple[str, ...]:
    """The arms of `--arms` (comma-separated), each of ARMS or toward_all_<t> with 0 < t < 1 (which
    needs encoder and all_labels)."""
    arms = tuple(a.strip() for a in text.split(",") if a.strip())
    for a in arms:
        t = a[len(TOWARD):] if a.startswith(TOWARD) else None
        ok = a in ARMS or (t is not None and t.replace(".", "", 1).isdigit() and 0 < float(t) < 1)
        if not ok:
            raise ValueError(f"arm {a!r}: expected one of {', '.join(ARMS)} or {TOWARD}<t>, 0 < t < 1")
    if any(a.startswith(TOWARD) for a in arms) and not {"encoder", "all_labels"} <= set(arms):
        raise ValueError(f"{TOWARD}<t> arms need the encoder and all_labels arms")
    if not arms:
        raise ValueError("no arm")
    return arms


def data_term(fit: ResponseFit, X: Tensor, Y: Tensor, codes: Tensor) -> float:
    """Mean over rows of sum_c (x_c - G_c(y; codes))^2 / noise_var_c."""
    with torch.no_grad():
        return float(((X - fit.model(Y, codes)) ** 2 / fit.noise_var).sum(-1).mean())


def learning_curve(F: np.ndarray, Z: np.ndarray, code_var: np.ndarray,
                   sizes: tuple[int, ...] = (36, 72, 108, 144), draws: int = 8,
                   seed: int = 0) -> dict[str, list[float]]:
    """The encoder's leave-one-unit-out R^2 learnt from random subsets of n units (n in `sizes`, and
    all), `draws` subsets each: {n: [R^2 of each draw]}."""
    g = np.random.default_rng(seed)
    out = {}
    for n in [m for m in sizes if m < len(F)] + [len(F)]:
        picks = [g.choice(len(F), n, replace=False) for _ in range(draws)] if n < len(F) else [np.arange(n)]
        out[str(n)] = [CodeEncoder.fit(F[i], Z[i], code_var).loo_r2 for i in picks]
    return out


def encoders(fit: ResponseFit, feats: dict[str, np.ndarray], own: list[str],
             more: tuple[np.ndarray, np.ndarray] | None = None) -> dict[str, CodeEncoder]:
    """`encoder`: learnt on every unit of the response model; `encoder_own`: on the registry's own
    training units only; `encoder_more`: on every unit of the response model and the encoder-only
    units `more` (features (m, f), codes (m, C, k))."""
    ids = fit.unit_ids
    Z, var = fit.model.codes.detach().cpu().numpy(), fit.code_var.cpu().numpy()
    F, mine = np.stack([feats[u] for u in ids]), [ids.index(u) for u in own]
    out = {"encoder": CodeEncoder.fit(F, Z, var),
           "encoder_own": CodeEncoder.fit(F[mine], Z[mine], var)}
    if more is not None:
        out["encoder_more"] = CodeEncoder.fit(np.concatenate([F, more[0]]), np.concatenate([Z, more[1]]), var)
    return out


def unlabeled_rows(arrays: FleetArrays, stream: CalibrationStream, unit: str, args: Settings, seed: int,
                   presses: Presses | None = None) -> np.ndarray:
    """A unit's unlabeled rows: its stream's first `args.seconds` (`first`), or `args.seconds` of
    contact as whole presses drawn at random from `presses` (default: every press of the stream),
    seeded by the run's seed and the unit's id (`spread`)."""
    if args.unlabeled == "first":
        return stream.unlabeled(args.seconds)
    if presses is None:
        return stream_ordinary_use(arrays, unit, stream, args.seconds, seed).rows
    return ordinary_use(presses, args.seconds, ordinary_use_seed(seed, unit)).rows


def training_features(ctx: Context, arrays: FleetArrays, opts: Options, ids: list[str],
                      args: Settings, seed: int) -> dict[str, np.ndarray]:
    """Stream features of the response model's training units (the run's extra units included),
    from their unlabeled rows, read as a new unit's are."""
    extra = None
    if opts.extra_units is not None and not set(ids) <= set(arrays.units):
        extra = load_extra(ctx, opts.extra_units.registry, opts.extra_units.data(), arrays)
    feats = {}
    for u in ids:
        a = arrays if u in arrays.units else extra
        if a is None:
            raise AnytipError(f"response model unit {u!r} is in neither the registry nor the extra units")
        stream = calibration_stream(a, u, opts.calibration_protocol, interleave=opts.calibration_interleave)
        feats[u] = stream_features(a.pressure[unlabeled_rows(a, stream, u, args, seed)])
    return feats


def whole_stream(arrays: FleetArrays, stream: CalibrationStream, rows: int, hz: float
                 ) -> tuple[Tensor, Tensor, float]:
    """`rows` evenly spaced labeled rows of a unit's whole stream: pressures (n, C) Pa, labels (n, D)
    and the effective row count of its robot time at `hz` (what the `all_labels` codes are fitted
    on)."""
    whole = stream.rows[evenly_spaced(len(stream.rows), rows).numpy()]
    n_eff = float(stream.seconds[-1]) * hz
    return torch.from_numpy(arrays.pressure[whole]), torch.from_numpy(arrays.targets[whole]), n_eff


def encoder_only_units(ctx: Context, like: FleetArrays, opts: Options, fit: ResponseFit,
                       recipe: ResponseRecipe, root: Path, args: Settings, seed: int, chunk: int = 32
                       ) -> tuple[list[str], np.ndarray, np.ndarray]:
    """Units of another registry (`--encoder-units`) that only teach the encoder: their ids, stream
    features (m, f) and codes (m, C, k), fitted by the frozen response model on `args.rows` evenly
    spaced labeled rows of each unit's whole stream (as the `all_labels` arm fits a unit's). No
    network or response model trains on them. Read `chunk` units at a time to bound memory."""
    registry = Registry(root, create=False)
    model = ctx.provenance["sensor_model"]
    _, records = select_runs(registry, DataConfig(sensor_model=model, protocol=None), ctx.spec.seed)
    units = sorted({r.unit for r in records})
    clash = sorted(set(units) & (set(like.units) | set(fit.unit_ids)))
    if clash:
        raise AnytipError(f"--encoder-units {root}: {len(clash)} of its units are the run's own "
                          f"({', '.join(clash[:4])})")
    feats, codes = [], []
    for a in range(0, len(units), chunk):
        part = set(units[a : a + chunk])
        arrays = load_arrays(registry, [r for r in records if r.unit in part])
        X, Y, n_eff = [], [], []
        for u in arrays.units:
            stream = calibration_stream(arrays, u, opts.calibration_protocol,
                                        interleave=opts.calibration_interleave)
            feats.append(stream_features(arrays.pressure[unlabeled_rows(arrays, stream, u, args, seed)]))
            x, y, eff = whole_stream(arrays, stream, args.rows, opts.rig.effective_hz)
            X.append(x)
            Y.append(y)
            n_eff.append(eff)
        codes.append(fit_codes(fit, X, Y, n_eff, recipe, seed).numpy())
        print(f"encoder units: {min(a + chunk, len(units))} of {len(units)}", flush=True)
    return units, np.stack(feats), np.concatenate(codes)


def unit_codes(fit: ResponseFit, recipe: ResponseRecipe, start: LoadedModels, arrays: FleetArrays,
               sd: SeedData, opts: Options, u: str, args: Settings, coders: dict[str, CodeEncoder], seed: int,
               candidates: Tensor, scale: ForceScale | None = None, draws: tuple[Tensor, ...] = ()
               ) -> tuple[dict[str, Tensor], dict]:
    """Unit u's codes of each network arm, and what its fits found; `candidates` (S, D): the
    training units' labeled contacts the `joint_search` and `joint_scale` arms search; `scale`: the
    `joint_scale` arms' prior; `draws`: the `joint_scale_draws` arm's other candidate draws."""
    arms, rows = args.arms, args.rows
    ev, n_eff = sd.evals[u], args.seconds * opts.rig.effective_hz
    unlabeled = unlabeled_rows(arrays, ev.stream, u, args, seed, ev.presses)
    stream = unlabeled[evenly_spaced(len(unlabeled), rows).numpy()]
    X, Y = torch.from_numpy(arrays.pressure[stream]), torch.from_numpy(arrays.targets[stream])
    zero = torch.zeros(fit.model.n_channels, fit.model.config.code_dim)
    labelled = fit_codes(fit, [X], [Y], [n_eff], recipe, seed)[0]
    codes = {"zero": zero, "stream_labels": labelled}
    found = {"unlabeled_rows": int(len(stream)), "data_term_truth": data_term(fit, X, Y, labelled),
             "code_rms_truth": float(labelled.pow(2).mean().sqrt())}
    feats = stream_features(arrays.pressure[unlabeled]) if coders else None
    for name, coder in coders.items():
        codes[name] = coder(feats)
        found[f"code_rms_{name}_off_truth"] = float((codes[name] - labelled).pow(2).mean().sqrt())
    if "all_labels" in arms:
        Xa, Ya, all_eff = whole_stream(arrays, ev.stream, rows, opts.rig.effective_hz)
        codes["all_labels"] = fit_codes(fit, [Xa], [Ya], [all_eff], recipe, seed)[0]
        for name in coders:
            off = codes[name] - codes["all_labels"]
            found[f"code_rms_{name}_off_all"] = float(off.pow(2).mean().sqrt())
        found["code_rms_zero_off_all"] = float(codes["all_labels"].pow(2).mean().sqrt())
    for arm in arms:
        if arm.startswith(TOWARD):  # an encoder whose code error is (1 - t) of this one's
            t = float(arm[len(TOWARD):])
            codes[arm] = codes["encoder"] + t * (codes["all_labels"] - codes["encoder"])
    if set(JOINT) & set(arms):
        Y0 = predict_rows(start.model, start.in_scaler, start.out_scaler, arrays, [stream])[0]
        Y0 = torch.from_numpy(Y0)
        mean, std = fit.model.label_mean, fit.model.label_std
        found |= {"data_term_start": data_term(fit, X, Y0, zero),
                  "contact_error_start": float(((Y0 - Y) / std).pow(2).mean().sqrt()),
                  "objective_at_truth": joint_objective(fit, X, (Y0 - mean) / std, n_eff / len(X),
                                                        (Y - mean) / std, labelled, args.pull)}
        starts = {"joint": None, "joint_truth": (labelled, Y)}
        cols = tuple(arrays.force_columns)
        found["force_ms_truth"] = mean_square_force(Y, cols)
        if {"joint_search", "joint_scale"} & set(arms):
            z, c = starts["joint_search"] = starts["joint_scale"] = searched_start(
                fit, recipe, X, n_eff, candidates, seed, args.rounds)
            found |= {"code_rms_search_off_truth": float((z - labelled).pow(2).mean().sqrt()),
                      "contact_error_search": float(((c - Y) / std).pow(2).mean().sqrt()),
                      "force_ms_search": mean_square_force(c, cols)}
        if scale is not None:
            found |= {"force_ms_prior": scale.mean, "force_ms_prior_sd": scale.var**0.5}
        for arm, from_codes in (("joint_scale_start", None), ("joint_scale_encoder", codes.get("encoder"))):
            if arm in arms:
                z, c = starts[arm] = searched_start(fit, recipe, X, n_eff, candidates, seed, args.rounds,
                                                    scale, from_codes)
                tag = "scaled_search" if from_codes is None else "encoder_search"
                found |= {f"code_rms_{tag}_off_truth": float((z - labelled).pow(2).mean().sqrt()),
                          f"contact_error_{tag}": float(((c - Y) / std).pow(2).mean().sqrt())}
        ends = {}
        for arm in [a for a in starts if a in arms]:
            codes[arm], contacts, trace = joint_fit(fit, X, Y0, n_eff, args.iterations, args.pull,
                                                    starts[arm], scale if arm in SCALED else None)
            ends[arm] = contacts
            found |= {f"data_term_{arm}": data_term(fit, X, contacts, codes[arm]),
                      f"force_ms_{arm}": mean_square_force(contacts, cols),
                      "objective" if arm == "joint" else f"objective_{arm}": trace,
                      f"code_rms_{arm}_off_truth": float((codes[arm] - labelled).pow(2).mean().sqrt()),
                      f"contact_error_{arm}": float(((contacts - Y) / std).pow(2).mean().sqrt())}
        if "joint_scale_rescaled" in arms:
            arm = "joint_scale_rescaled"
            codes[arm], contacts = rescaled_codes(fit, recipe, X, n_eff, ends["joint_scale_encoder"], scale,
                                                  seed)
            found |= {f"data_term_{arm}": data_term(fit, X, contacts, codes[arm]),
                      f"force_ms_{arm}": mean_square_force(contacts, cols),
                      f"code_rms_{arm}_off_truth": float((codes[arm] - labelled).pow(2).mean().sqrt())}
        if "joint_scale_draws" in arms:  # draw 0 is joint_scale_start's, reused where that arm ran
            pools, first = (candidates, *draws), codes.get("joint_scale_start")
            codes["joint_scale_draws"], of_draws = mean_of_draws(fit, recipe, X, Y0, n_eff, pools, seed, args,
                                                                 scale, labelled, first)
            found |= of_draws
        if {"joint_scale_start", "joint_scale_encoder"} <= set(arms):  # do the two starts end apart?
            apart = codes["joint_scale_encoder"] - codes["joint_scale_start"]
            found["code_rms_encoder_start_off_zero_start"] = float(apart.pow(2).mean().sqrt())
    if {"plan", "plan_joint", "plan_joint_all"} & set(arms):
        plan = plan_of(sd, u, Budget(args.plan_seconds, "seconds", opts.plan_strategies[0]), opts, seed)
        Xp, Yp = torch.from_numpy(arrays.pressure[plan.rows]), torch.from_numpy(arrays.targets[plan.rows])
        codes["plan"] = fit_codes(fit, [Xp], [Yp], [plan.n_effective], recipe, seed)[0]
        found["code_rms_plan_off_truth"] = float((codes["plan"] - labelled).pow(2).mean().sqrt())
        for arm, plan_rows in (("plan_joint", LabelFreeRecipe.plan_rows), ("plan_joint_all", None)):
            if arm not in arms:
                continue
            free = LabelFreeRecipe(args.seconds, args.rows, args.pull, iterations=args.iterations,
                                   plan_rows=plan_rows)
            began = time.perf_counter()
            codes[arm] = plan_and_use_codes(fit, recipe, free, X, Y0, n_eff, candidates, seed,
                                            Labeled(Xp, Yp, plan.n_effective), codes["plan"], scale)[0]
            found[f"seconds_{arm}"] = time.perf_counter() - began
            found[f"code_rms_{arm}_off_truth"] = float((codes[arm] - labelled).pow(2).mean().sqrt())
    return {a: c for a, c in codes.items() if a in arms}, found


def mean_of_draws(fit: ResponseFit, recipe: ResponseRecipe, X: Tensor, Y0: Tensor, n_eff: float,
                  draws: tuple[Tensor, ...], seed: int, args: Settings, scale: ForceScale | None,
                  truth: Tensor, first: Tensor | None = None) -> tuple[Tensor, dict]:
    """The mean (C, k) of the scale-held fit's codes (`label_free_codes`), one fit searched among each
    draw of candidate contacts (S, D), the first draw's given as `first` where already fitted; each
    draw's and the mean's RMS distance from `truth` (C, k), and the draws' RMS spread about their
    mean."""
    free = LabelFreeRecipe(args.seconds, args.rows, args.pull, rounds=args.rounds, iterations=args.iterations)
    each = [] if first is None else [first]
    for candidates in draws[len(each):]:
        each.append(label_free_codes(fit, recipe, free, X, Y0, n_eff, candidates, seed, scale)[0])
    stacked = torch.stack(each)
    mean = stacked.mean(0)
    rms = lambda t: float(t.pow(2).mean().sqrt())  # noqa: E731
    return mean, {"code_rms_draws_off_truth": [rms(z - truth) for z in each],
                  "code_rms_joint_scale_draws_off_truth": rms(mean - truth),
                  "code_rms_draws_spread": rms(stacked - mean)}


@dataclass(frozen=True)
class Settings:
    """What the command line chose: the arms, seconds of unlabeled stream, rows fitted, joint-fit
    steps, the `plan` arm's robot-seconds."""

    arms: tuple[str, ...] = ARMS
    seconds: float = 600.0
    rows: int = 4096
    iterations: int = 30
    plan_seconds: float = 120.0
    encoder_units: Path | None = None
    unlabeled: str = "first"
    pull: float = 1.0
    validation_only: bool = False
    rounds: int = SEARCH.rounds
    draws: int = DRAWS
    search_draw: int = 0


Curves = dict[str, dict[str, list[float]]]  # per seed: {unit count: the encoder's R^2 per draw}


def run(run_dir: Path, registry: Path, args: Settings) -> tuple[list[dict], Curves]:
    """Every (unit, arm)'s row, and per seed the encoder's R^2 by training-unit count (with
    --encoder-units)."""
    spec = load_spec(run_dir / "config.yaml", ["options.adapters=[]"])
    ctx = Context(spec, Registry(registry, create=False), run_dir, torch.device("cpu"), False, {})
    opts = parse_options(ctx)
    if opts.response is None:
        raise AnytipError(f"{run_dir}: its spec has no options.response")
    arrays = load(ctx, min_units(ctx))
    refs = {(r["seed"], r["unit"]): r for r in read_json(run_dir / "metrics.json")["results"]
            if r["method"] == "per_unit"}
    out: list[dict] = []
    feats: dict[str, np.ndarray] = {}
    curves: Curves = {}
    for seed in spec.all_seeds:
        if args.unlabeled == "spread":
            feats = {}  # the presses drawn depend on the seed
        sd = prepare(ctx, arrays, opts, seed)  # the run's split; its extra units are not needed here
        recorded = read_json(run_dir / "provenance.json")["cross_sensor"][f"seed{seed}"]["units"]
        if sd.split.to_json() != recorded:
            raise AnytipError(f"seed {seed}: the split differs from the run's")
        path = run_dir / "models" / f"response_seed{seed}.safetensors"
        saved = load_response(path)
        fit, recipe = ResponseFit.from_loaded(saved), ResponseRecipe.from_saved(saved.meta["recipe"])
        start = load_models(start_network_path(path))
        coders: dict[str, CodeEncoder] = {}
        if {"encoder", "encoder_own", "encoder_more", "joint_scale_encoder"} & set(args.arms):
            missing = [u for u in fit.unit_ids if u not in feats]
            feats |= training_features(ctx, arrays, opts, missing, args, seed)
            more = None
            if args.encoder_units is not None:
                _, Fm, Zm = encoder_only_units(ctx, arrays, opts, fit, recipe, args.encoder_units, args, seed)
                more = (Fm, Zm)
                F = np.concatenate([np.stack([feats[u] for u in fit.unit_ids]), Fm])
                curve = learning_curve(F, np.concatenate([fit.model.codes.detach().cpu().numpy(), Zm]),
                                       fit.code_var.cpu().numpy())
                print(f"seed {seed} encoder R^2 by units: "
                      + ", ".join(f"{n}: {np.mean(r):.3f}" for n, r in curve.items()), flush=True)
                curves[str(seed)] = curve
            coders = encoders(fit, feats, [u for u in fit.unit_ids if u in sd.split.train], more)
            for name, c in coders.items():
                print(f"seed {seed} {name}: penalty {c.alpha:.3g}, leave-one-unit-out R^2 {c.loo_r2:.3f}",
                      flush=True)
        units = [*sd.split.val] + ([] if args.validation_only else [*sd.split.test])
        codes: dict[tuple[str, str], Tensor] = {}
        found: dict[str, dict] = {}
        source = (transfer_source(ctx, sd, fit, recipe, saved.meta, seed)
                  if set(args.arms) - {"pooled", "input_stats"} else None)  # only arms with codes need it
        candidates = (torch.zeros(0, arrays.targets.shape[1]) if source is None
                      else search_candidates(source.Y, SEARCH.candidates, seed, args.search_draw))
        scale = None
        if set(SCALED) & set(args.arms):
            use = LabelFreeRecipe(args.seconds, args.rows)
            scale = fleet_force_scale(arrays, sorted(sd.split.train), opts.calibration_protocol,
                                      opts.calibration_interleave, use, seed)
            if scale is None:
                raise AnytipError(f"arms {', '.join(SCALED)}: the sensor model has no force target")
        draws = tuple(search_candidates(source.Y, SEARCH.candidates, seed + k) for k in range(1, args.draws)
                      ) if source is not None and "joint_scale_draws" in args.arms else ()
        for u in units:
            mine, found[u] = unit_codes(fit, recipe, start, arrays, sd, opts, u, args, coders, seed,
                                        candidates, scale, draws)
            codes |= {(u, a): c for a, c in mine.items()}
            found[u] |= {f"{n}_penalty": c.alpha for n, c in coders.items()}
            found[u] |= {f"{n}_loo_r2": c.loo_r2 for n, c in coders.items()}
            said = ", ".join(f"{k} {v:.3g}" for k, v in found[u].items()
                             if not isinstance(v, list))
            print(f"seed {seed} {u}: {said}", flush=True)
        preds = arm_predictions(ctx, arrays, sd, fit, recipe, start, source, codes, args, seed, units)
        for u in units:
            test = sd.evals[u].test_rows
            Xt, Yt = torch.from_numpy(arrays.pressure[test]), torch.from_numpy(arrays.targets[test])
            for arm in args.arms:
                row = {"seed": seed, "unit": u, "arm": arm, "role": "val" if u in sd.split.val else "test",
                       **scores(preds[u, arm], Yt.numpy(), arrays.layout), **found[u]}
                if (u, arm) in codes:
                    rms = residual_rms(fit, Xt, Yt, codes[u, arm])
                    row["test_residual_pa"] = float((rms**2).mean() ** 0.5)
                if (seed, u) in refs:
                    row |= ratio_fields(row, refs[seed, u], arrays.layout)
                out.append(row)
        for arm in args.arms:
            print(f"seed {seed} {arm:>14}: {summary(out, arm)}", flush=True)
    return out, curves


def transfer_source(ctx: Context, sd: SeedData, fit: ResponseFit, recipe: ResponseRecipe, meta: dict,
                    seed: int) -> SourceRows:
    """The rows a new unit's network is trained on once transferred: the response model's source
    units (the registry's training units, by its metadata), as the run drew them."""
    ids = [str(u) for u in meta.get("source_unit_ids", [])]
    if not ids or not set(ids) <= set(sd.train.unit_ids):
        raise AnytipError(f"{ctx.run_dir}: its response model's source units are not the registry's "
                          f"training units of seed {seed} (a model that transfers extra units' rows)")
    mine = sd.train.subset([sd.train.unit_ids.index(u) for u in ids])
    return source_rows(fit, mine, recipe.source_rows, seed)


def arm_predictions(ctx: Context, arrays: FleetArrays, sd: SeedData, fit: ResponseFit, recipe: ResponseRecipe,
                    start: LoadedModels, source: SourceRows | None, codes: dict[tuple[str, str], Tensor],
                    args: Settings, seed: int, units: list[str]) -> dict[tuple[str, str], np.ndarray]:
    """Each (unit of `units`, arm)'s predictions on the unit's test rows: a network trained on the rows
    transferred by the arm's codes, the pooled start network itself, or the run's shared model
    without adapters scaled by the unit's unlabeled input statistics (`input_stats`, today's
    zero-shot method)."""
    tests = [sd.evals[u].test_rows for u in units]
    preds: dict[tuple[str, str], np.ndarray] = {}
    if codes:
        assert source is not None
        jobs = list(codes)
        nets = unit_networks(((transfer(fit, source, codes[j]), source.Y) for j in jobs), ctx.spec.model,
                             recipe, seed, [f"{u}/{a}" for u, a in jobs], arrays.output_names, start=start)
        preds |= dict(zip(jobs, predict_rows(nets.model, nets.in_scaler, nets.out_scaler, arrays,
                                             [sd.evals[u].test_rows for u, _ in jobs]), strict=True))
    if "pooled" in args.arms:
        preds |= {(u, "pooled"): predict_rows(start.model, start.in_scaler, start.out_scaler, arrays, [t])[0]
                  for u, t in zip(units, tests, strict=True)}
    if "input_stats" in args.arms:
        shared = load_shared(ctx.run_dir / "models" / f"shared_none_seed{seed}.safetensors")
        unlabeled = [torch.from_numpy(arrays.pressure[sd.evals[u].stream.unlabeled(args.seconds)])
                     for u in units]
        empty_x, empty_y = torch.zeros(0, arrays.pressure.shape[1]), torch.zeros(0, arrays.targets.shape[1])
        model, stats = calibrate_and_fold(shared, unlabeled, [empty_x] * len(units), [empty_y] * len(units),
                                          [0] * len(units), [0.0] * len(units), seed=seed)
        found = predict_rows(model, stats, shared.out_scaler, arrays, tests)
        preds |= {(u, "input_stats"): p for u, p in zip(units, found, strict=True)}
    return preds


def summary(rows: list[dict], arm: str) -> str:
    """The held-out units' mean force / angle ratio and every unit's mean test-patch residual."""
    mine = [r for r in rows if r["arm"] == arm]
    held = [r for r in mine if any(k.endswith("_ratio") for k in r)]
    text = "no held-out unit"
    if held:
        ratios = [k for k in held[0] if k.endswith("_ratio")]
        text = "held-out " + " / ".join(f"{k.removesuffix('_ratio')} {np.mean([r[k] for r in held]):.2f}x"
                                        for k in ratios) + f" ({len(held)} units)"
    if "test_residual_pa" in mine[0]:
        text += f"; test-patch residual {np.mean([r['test_residual_pa'] for r in mine]):.0f} Pa"
    return text


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="a cross_sensor run with a pooled start")
    parser.add_argument("--registry", type=Path, required=True, help="the registry the run read")
    parser.add_argument("--out", type=Path, required=True, help="JSON file for the rows")
    parser.add_argument("--seconds", type=float, default=600.0, help="seconds of unlabeled stream read")
    parser.add_argument("--unlabeled", choices=("first", "spread"), default="first",
                        help="the stream's first --seconds, or --seconds of contact as random whole presses "
                             "from anywhere in it (ordinary use spread over the dome)")
    parser.add_argument("--rows", type=int, default=4096, help="evenly spaced rows of them fitted")
    parser.add_argument("--iterations", type=int, default=30, help="damped Gauss-Newton steps")
    parser.add_argument("--pull", type=float, default=1.0,
                        help="lam of the joint fits: the pull towards the start network's contacts")
    parser.add_argument("--rounds", type=int, default=SEARCH.rounds,
                        help="the searched start's alternations of contact search and code fit (0: codes "
                             "zero, each row's nearest contact under them)")
    parser.add_argument("--draws", type=int, default=DRAWS,
                        help="candidate draws the joint_scale_draws arm averages the codes of")
    parser.add_argument("--search-draw", type=int, default=0,
                        help="which draw of the training units' labeled contacts the search arms read (0: "
                             "the seed's own order, as every run before entry 222; "
                             "`options.response.label_free.search_draw`)")
    parser.add_argument("--plan-seconds", type=float, default=120.0, help="robot-seconds of the `plan` arm")
    parser.add_argument("--validation-only", action="store_true",
                        help="fit and score the validation units only (what a method is chosen on)")
    parser.add_argument("--encoder-units", type=Path, default=None,
                        help="a registry whose units only teach the encoder (arm encoder_more)")
    parser.add_argument("--arms", default=",".join(a for a in ARMS if a != "encoder_more"),
                        help=f"comma-separated, of {', '.join(ARMS)} and {TOWARD}<t> (default: all but "
                             "encoder_more)")
    args = parser.parse_args(argv)
    try:
        arms = arm_names(args.arms)
    except ValueError as e:
        parser.error(f"--arms {args.arms!r}: {e}")
    if args.search_draw < 0:
        parser.error(f"--search-draw {args.search_draw}: a draw is 0 or more")
    if "joint_scale_rescaled" in arms and "joint_scale_encoder" not in arms:
        parser.error("the joint_scale_rescaled arm rescales joint_scale_encoder's fit: list both")
    if ("encoder_more" in arms) != (args.encoder_units is not None):
        parser.error("the encoder_more arm and --encoder-units go together")
    torch.set_num_threads(1)
    try:
        rows, curves = run(args.run, args.registry, Settings(arms, args.seconds, args.rows, args.iterations,
                                                             args.plan_seconds, args.encoder_units,
                                                             args.unlabeled, args.pull,
                                                             args.validation_only, args.rounds, args.draws,
                                                             args.search_draw))
    except AnytipError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    args.out.parent.mkdir(parents=True, exist_ok=True)
    found = {"run": str(args.run), "seconds": args.seconds, "unlabeled": args.unlabeled, "pull": args.pull,
             "iterations": args.iterations, "search_rounds": args.rounds, "search_draw": args.search_draw,
             "rows": rows}
    if curves:
        found["encoder_r2_by_units"] = curves
    args.out.write_text(json.dumps(found, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
