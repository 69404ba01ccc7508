"""Calibration by response transfer again, on a finished run's own response models and references.

A cross_sensor run with `options.response` saved each seed's response model
(`models/response_seed<s>.safetensors`) and scored every held-out unit against its converged
per-unit reference (`per_unit` rows). Both are deterministic, and the reference is what costs
most of a run. This script re-runs only the response transfer of the run's validation and
held-out units, on the same splits, plans and test patches, with the spec's options changed
by `--set` (a new recipe for the unit's network or its codes, intervals), and writes a run
directory whose rows are the run's references beside the new response rows, with the new
response models (their new recipe and intervals record) and copies of the run's shared models,
so `anytip calibrate --model OUT` works as on the run:

    python scripts/rescore_response.py RUN_DIR --registry data/fleet88 --out OUT \
        --set options.response.inverse_epochs=40 --set "options.intervals={folds: 5, level: 0.9}"

The validation units choose the method and learn the intervals' fleet factor, as in a run; the
held-out units are only scored. With unchanged options the rows equal the run's own
`response@` rows. The response model is reused, and options that would change it (code_dim,
hidden, layers, steps, ...) are refused, unless `--retrain` asks for each seed's response model to
be trained again, on the run's own training units (and its `extra_units`), with the options given:

    python scripts/rescore_response.py RUN_DIR --registry data/fleet24 --out OUT --retrain \
        --set options.response.steps=20000

A retrained model is saved as soon as it is trained: the same command on an OUT that an
interruption left without metrics.json reuses it, as `anytip run` does in place. Retraining takes
the spec's `threads` (`--set threads=N`); a rescoring alone runs on one thread, so that folds can
run side by side.

`--response-model FILE` (`{seed}` replaced by the seed) takes each seed's response model from
elsewhere: one trained on the seed's training units and on units this machine does not hold (many
simulated units trained on a GPU by `scripts/response_many_units.py`). It must have learnt every
training unit of the split and no validation or held-out unit; the run's `extra_units` are not
read (they only trained the run's response model), and a new unit's rows are transferred from the
registry's own training units (`transfer_from: registry`):

    python scripts/rescore_response.py RUN_DIR --registry data/fleet88 --out OUT \
        --response-model 'build/many_units/fleet88_seed{seed}_extra1024.safetensors'
"""

from __future__ import annotations

import argparse
import shutil
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import torch

from anytip.config import load_spec, public_config
from anytip.data.arrays import FleetArrays
from anytip.data.registry import Registry
from anytip.errors import AnytipError
from anytip.models.io import ModelFileError, load_models, load_response
from anytip.models.response import ResponseConfig
from anytip.pipelines.common import Context, load, load_extra
from anytip.pipelines.cross_sensor import min_units, prepare, reference_tag, reference_trials
from anytip.pipelines.cross_sensor_options import Options, parse_options
from anytip.pipelines.cross_sensor_response import check_trained_on, response_rows, val_by_method
from anytip.rundir import check_run_dir, code_version, read_json, write_config, write_json, write_metrics
from anytip.runner import rewrite_report
from anytip.sensor.protocols import is_designed, is_test_session
from anytip.train.metrics import scores, target_key
from anytip.train.response import TRAINING_FIELDS, ResponseFit, ResponseRecipe
from anytip.train.shared_split import SeedData, predict_rows


def rescored_from(run: Path, overrides: list[str], retrain: bool, response_model: str | None,
                  added: tuple[str, ...]) -> str:
    """The sentence a rescored run's description starts with, so that its report says what was
    scored again and how (the source spec's description follows it, budgets and methods as the
    source had them)."""
    how = [f"`--set {o}`" for o in overrides]
    how += ["the response models trained again"] if retrain else []
    how += [f"the response models `{response_model}`"] if response_model else []
    how += [f"the runs of `{p}` added" for p in added]
    return (f"Rescored by response transfer alone from `{run}`"
            f"{' with ' + ', '.join(how) if how else ''}; the source's description:")


def rescore(run: Path, registry: Path, out: Path, overrides: list[str], retrain: bool = False,
            response_model: str | None = None, added: tuple[str, ...] = (), paired_only: bool = False,
            references: Path | None = None) -> Path:
    """The run's references and its units calibrated again by response transfer, in `out`; with
    `retrain`, each seed's response model is trained again on the run's training units with the
    options given; with `response_model` (a file name, `{seed}` replaced), each seed's model is
    read from there (otherwise the run's own models are reused). `added`: designed calibrations'
    protocols (`plan<seconds>`) whose runs the registry holds beyond the run's, for the `designed`
    strategy's plans; every other run must be the run's own, unless `paired_only`: the registry holds
    the same units and runs simulated otherwise (another fleet config's run conditions), so the rescored
    rows stand only beside each other, per unit; their ratios to the run's references (scored on the
    run's registry) mean nothing, and the report says so. `added` may name `retest`, a test session
    of every unit: the held-out units are then tested on its rows alone, and `references` (a directory
    with the run's saved per-unit references, `per_unit_seed<s>[_lr<j>][_start<k>]`) scores each reference
    again on them, with the learning rate and start the run kept for its unit (without a test session, on the
    run's own test rows: the run's rows back, a check of the saved references). A test session
    without `references` needs `paired_only`: the rows then keep the run's references, scored on
    its own test rows, and only the rescored methods compare (a run that saved no references)."""
    wrong = [p for p in added if not (is_designed(p) or is_test_session(p))]
    if wrong:
        raise AnytipError(f"--added-protocol {wrong[0]}: only a designed calibration's runs (plan<seconds>) "
                          "or a test session's (retest) may join a rescoring: no unit is trained on them")
    if any(map(is_test_session, added)) and references is None and not paired_only:
        raise AnytipError("a test session (--added-protocol retest) moves the held-out units' test rows, so "
                          "their references are scored again: give --references with it (or --paired-only, "
                          "whose rows compare only with each other)")
    if retrain and response_model:
        raise AnytipError("--retrain and --response-model exclude each other")
    said = rescored_from(run, overrides, retrain, response_model, added)
    if response_model:  # the extra units trained that model; they are not read here
        overrides = [*overrides, "options.extra_units=null"]
    spec = load_spec(run / "config.yaml", [*overrides, "options.adapters=[]"])
    spec = spec.model_copy(update={"description": f"{said} {spec.description}".strip()})
    if retrain:  # training a response model again takes the spec's threads, as `anytip run` gave it
        torch.set_num_threads(spec.threads)
    old = read_json(run / "provenance.json")
    ctx = Context(spec, Registry(registry, create=False), out, torch.device("cpu"), False,
                  {"spec_file": str(run / "config.yaml")})
    opts = parse_options(ctx)
    if opts.response is None:
        raise AnytipError(f"{run}: its spec has no options.response")
    arrays = load(ctx, min_units(ctx))
    own = [r.run_id for r in arrays.runs if r.protocol not in added]
    if not paired_only and ctx.registry.content_hash(own) != old.get("selection_content_hash"):
        raise AnytipError(f"{registry}: its runs differ from those {run} was run on"
                          f"{' (the runs of ' + ', '.join(added) + ' set aside)' if added else ''}")
    if response_model and opts.response.transfer_from != "registry":
        raise AnytipError("--response-model: a new unit's rows come from the registry's own training units; "
                          "set options.response.transfer_from=registry")
    paths = {s: Path(response_model.format(seed=s)) if response_model else
             run / "models" / f"response_seed{s}.safetensors" for s in spec.all_seeds}
    saved = {} if retrain else {s: load_response(paths[s]) for s in spec.all_seeds}
    for seed, model in saved.items():
        try:
            _check_same_model(model.model.config, model.meta.get("recipe", {}), opts, seed)
        except (TypeError, ValueError) as e:  # a recipe in the model's header that no run wrote
            raise AnytipError(f"{paths[seed]}: {e}") from None
        units = old.get("cross_sensor", {}).get(f"seed{seed}", {}).get("units")
        roles = ("train", "val", "test")
        if not isinstance(units, dict) or not all(isinstance(units.get(k), list) for k in roles):
            raise AnytipError(f"{run / 'provenance.json'}: no unit split recorded for seed {seed}")
        try:
            check_trained_on([str(u) for u in model.meta.get("unit_ids", [])], units["train"],
                             [*units["val"], *units["test"]], seed)
        except AnytipError as e:
            raise AnytipError(f"{paths[seed]}: {e}") from None
    check_run_dir(out)  # an interrupted rescoring (no metrics yet) resumes in place
    (out / "models").mkdir(parents=True, exist_ok=True)
    write_config(out, public_config(spec))
    for shared in (run / "models").glob("shared_*"):  # the run's shared models: what `anytip calibrate` reads
        shutil.copy2(shared, out / "models" / shared.name)
    rows = [r for r in read_json(run / "metrics.json")["results"] if r["method"] == "per_unit"]
    start = time.perf_counter()
    for seed in spec.all_seeds:
        extra = None  # loaded per seed and dropped once its rows are in the training tensors (memory)
        if opts.extra_units is not None:  # they trained (or train) the response model
            extra = load_extra(ctx, opts.extra_units.registry, opts.extra_units.data(), arrays)
        sd = prepare(ctx, arrays, opts, seed, extra)
        if opts.response.label_free is None:  # only the label-free row's code encoder reads them again
            extra = None
        was = old["cross_sensor"][f"seed{seed}"]["units"]
        if any(list(getattr(sd.split, k)) != was.get(k) for k in ("train", "val", "test")):
            raise AnytipError(f"seed {seed}: the split differs from the run's")
        fit = ResponseFit.from_loaded(saved[seed]) if seed in saved else None
        if references is not None:
            rows = _scored_again(rows, references, arrays, sd, opts, seed)
        got = response_rows(ctx, arrays, sd, opts, seed, fit, extra)
        del extra
        base = {"seed": seed, "split": rows[0]["split"], "n_train_units": len(sd.split.train)}
        # units the response model learnt beside the registry's training units (the run's extra units,
        # or those of a model trained elsewhere), as a run's rows record them
        n_extra = sd.n_extra if fit is None else len(fit.unit_ids) - (sd.train.n_units - sd.n_extra)
        if n_extra:
            base["n_extra_units"] = n_extra
        rows += [dict(base, **r) for r in got.rows]
        ctx.provenance.setdefault("cross_sensor", {})[f"seed{seed}"] = {
            "units": sd.split.to_json(), "val_loss": val_by_method(got),
            "val_loss_units": val_by_method(got, per_unit=True)}
        print(f"seed {seed}: {len(got.rows)} held-out rows ({time.perf_counter() - start:.0f} s)", flush=True)
    ctx.provenance.update(rescored_from=str(run), overrides=overrides, seeds=spec.all_seeds,
                          retrained=retrain, response_model=response_model, code=code_version(),
                          paired_only=paired_only, references=None if references is None else str(references),
                          wall_s=round(time.perf_counter() - start, 2))
    keys = [target_key(name) for name in ctx.provenance["targets"]]
    write_metrics(out, rows, keys, spec=spec.name, pipeline=spec.pipeline)
    write_json(out / "provenance.json", ctx.provenance)
    report = rewrite_report(out)
    if paired_only:
        text = report.read_text()
        report.write_text(f"> {PAIRED_ONLY_NOTE}\n\n{text}")
    return report


def _scored_again(rows: list[dict[str, Any]], models: Path, arrays: FleetArrays, sd: SeedData, opts: Options,
                  seed: int) -> list[dict[str, Any]]:
    """The `per_unit` rows of `seed` scored again on their units' test rows now, each by the reference
    the run saved in `models` (`per_unit_seed<s>[_lr<j>][_start<k>]`, the learning rate and start the
    run kept for the unit), every saved unit predicted at once as the run did (so its own test rows give
    its rows back)."""
    lrs = list(opts.reference_lrs)
    preds: dict[str, dict[str, np.ndarray]] = {}
    for tag in (reference_tag(len(lrs), k, j) for k, j in reference_trials(opts)):
        path = models / f"per_unit_seed{seed}{tag}"
        try:
            saved = load_models(path)
        except ModelFileError as e:
            raise AnytipError(f"--references: {e}") from None
        units = [str(u) for u in saved.meta.get("unit_ids", [])]
        missing = [u for u in units if u not in sd.evals]
        if missing:
            raise AnytipError(f"--references: {path} holds units this split does not test ({missing[0]})")
        got = predict_rows(saved.model, saved.in_scaler, saved.out_scaler, arrays,
                           [sd.evals[u].test_rows for u in units])
        preds[tag] = dict(zip(units, got, strict=True))
    out = []
    for row in rows:
        if row["seed"] != seed:
            out.append(row)
            continue
        tag = reference_tag(len(lrs), lrs.index(row["reference_lr"]) if len(lrs) > 1 else 0,
                            row.get("reference_start", 0))
        if row["unit"] not in preds[tag]:
            raise AnytipError(f"--references: {models} holds no reference of unit {row['unit']}")
        target = arrays.targets[sd.evals[row["unit"]].test_rows]
        out.append(dict(row, **scores(preds[tag][row["unit"]], target, arrays.layout)))
    return out


PAIRED_ONLY_NOTE = ("Rescored with `--paired-only` on another registry than the run's: the `per_unit` rows "
                    "are the run's references, scored on its own registry, so every ratio to them here "
                    "means nothing; compare the rescored methods with each other, per unit.")


def _check_same_model(config: ResponseConfig, recipe: dict[str, Any], opts: Options, seed: int) -> None:
    """Refuse options that would have trained another response model than the one saved."""
    assert opts.response is not None
    asked, trained = opts.response.recipe(), ResponseRecipe.from_saved(recipe)
    differ = [k for k in TRAINING_FIELDS if getattr(asked, k) != getattr(trained, k)]
    if opts.response.config() != config or differ:
        raise AnytipError(f"seed {seed}: options.response asks for another response model than the saved one "
                          f"({', '.join(differ) or 'its shape'}); the saved models are reused, not retrained")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="a finished cross_sensor run with options.response")
    parser.add_argument("--registry", type=Path, required=True, help="the registry the run read")
    parser.add_argument("--out", type=Path, required=True,
                        help="a new directory for the rescored run (or one an interruption left)")
    parser.add_argument("--set", dest="overrides", action="append", default=[],
                        help="KEY=VALUE, as `anytip run --set`")
    parser.add_argument("--retrain", action="store_true",
                        help="train each seed's response model again on the run's training units with the "
                             "options given (otherwise the run's own response models are reused)")
    parser.add_argument("--added-protocol", action="append", default=[], metavar="PLAN",
                        help="a designed calibration (plan<seconds>) whose runs the registry holds beyond "
                             "the run's own, read by the `designed` plan strategy alone (repeatable)")
    parser.add_argument("--paired-only", action="store_true",
                        help="the registry holds the run's units and runs simulated otherwise: skip the "
                             "check that its runs are the run's; the rows then compare only with each other")
    parser.add_argument("--references", type=Path, metavar="DIR",
                        help="the run's saved per-unit references (per_unit_seed<s>[_lr<j>][_start<k>]), "
                             "scored again on the held-out units' test rows (needed with --added-protocol "
                             "retest, unless --paired-only)")
    parser.add_argument("--response-model", help="each seed's response model from this file ({seed} is "
                        "replaced by the seed) instead of the run's")
    args = parser.parse_args(argv)
    threads = torch.get_num_threads()  # given back on return: a caller in the same process keeps its own
    torch.set_num_threads(1)
    try:
        out = rescore(args.run, args.registry, args.out, args.overrides, args.retrain, args.response_model,
                      tuple(args.added_protocol), args.paired_only, args.references)
        print(f"report: {out}")
    except AnytipError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    finally:
        torch.set_num_threads(threads)
    return 0


if __name__ == "__main__":
    sys.exit(main())
