"""Command line: `anytip` (the main job), `anytip data ...` (the registry)."""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from anytip.errors import AnytipError
from anytip.rundir import dumps_json, write_text
from anytip.validation import mask_secrets

if TYPE_CHECKING:
    from anytip.data.registry import Registry


def _registry_path(args: argparse.Namespace) -> Path:
    from anytip.data.registry import default_registry_path

    return Path(args.registry) if args.registry else default_registry_path()


def _registry(args: argparse.Namespace, create: bool = False) -> Registry:
    """The registry of `--registry`; only `data import` and `data simulate` create one."""
    from anytip.data.registry import Registry

    return Registry(_registry_path(args), create=create)


def _print_runs(records, as_json: bool) -> None:
    from rich.console import Console
    from rich.table import Table

    if as_json:
        for rec in records:
            print(dumps_json(rec.to_json(), indent=None, sort_keys=True), end="")
        return
    table = Table(title=f"{len(records)} runs, {len({r.unit for r in records})} units")
    for col in ("run_id", "unit", "model", "orient.", "protocol", "source", "rows", "robot s"):
        table.add_column(col, justify="right" if col in ("orient.", "rows", "robot s") else "left")
    for r in records:
        table.add_row(
            r.run_id, r.unit, r.sensor_model, f"{r.orientation_deg:g}",
            (r.protocol or "-") + (" *" if r.protocol_set else ""),
            r.source, f"{r.rows:,}", f"{r.duration_s:,.0f}",
        )
    Console(width=max(140, Console().width)).print(table)
    if any(r.protocol_set for r in records):
        print("* protocol marked in the registry (`anytip data protocol`), not named by the run file")


def _print_models(layouts: dict[str, str], records) -> None:
    """One line per sensor model among `records`: its channel count and targets."""
    from anytip.data.runfile import describe_layout

    for model in sorted({r.sensor_model for r in records}):
        units = {r.unit for r in records if r.sensor_model == model}
        print(f"sensor model {model}: {describe_layout(layouts[model])} ({len(units)} units)")


def _sensor_model(args: argparse.Namespace, known: str) -> str:
    """`--sensor-model`, the fingertip's where none is given; an unknown one is named beside those the
    simulator has (`known` says what they are to the command, e.g. 'plans are designed for')."""
    from anytip.sensor import flat
    from anytip.sensor.geometry import SENSOR_MODEL

    model = args.sensor_model or SENSOR_MODEL
    if model != SENSOR_MODEL and model not in flat.DESIGNS:
        raise AnytipError(f"--sensor-model {model!r}: {known} {SENSOR_MODEL!r} and "
                          f"{', '.join(map(repr, flat.DESIGNS))}")
    return model


def cmd_simulate(args: argparse.Namespace) -> int:
    from anytip.data.plans import plan_points
    from anytip.data.simulated import simulate_flat_into, simulate_into
    from anytip.sensor import flat
    from anytip.sensor.fleet import FleetConfig, load_fleet_config
    from anytip.sensor.geometry import SENSOR_MODEL
    from anytip.sensor.protocols import PLAN_MOVE_S, design_protocol, designed_seconds, is_designed

    if args.units < 1 or args.seed < 0:
        raise AnytipError(f"--units must be >= 1 and --seed >= 0, got {args.units} and {args.seed}")
    model = _sensor_model(args, "the simulator knows")
    if model in flat.DESIGNS and args.fleet:
        raise AnytipError(f"--fleet configures the fingertip's fleet; --sensor-model {model!r} takes none")
    if model == SENSOR_MODEL and args.severity != 1.0:
        raise AnytipError("--severity is for edge-4baro and pad-16baro; the fingertip's variation is "
                          "set in its fleet config (--fleet, key 'severity')")
    protocols = [p for p in args.protocols.split(",") if p]
    plan_options = {"--move-s times the moves": args.move_s,
                    "--plan-points chooses the points": args.plan_points}
    for what, given in plan_options.items():
        if given is not None and not any(map(is_designed, protocols)):
            raise AnytipError(f"{what} of a designed plan (plan<seconds>); --protocols {args.protocols!r} "
                              f"has none")
    move_s = PLAN_MOVE_S if args.move_s is None else args.move_s
    if not (math.isfinite(move_s) and move_s > 0):
        raise AnytipError(f"--move-s must be a finite number of seconds > 0, got {args.move_s}")
    points = plan_points(model, args.plan_points)
    registry = _registry(args, create=True)
    start = time.perf_counter()
    if model in flat.DESIGNS:
        bad = [p for p in protocols if p not in flat.PROTOCOLS and not is_designed(p)]
        if bad:
            raise AnytipError(f"--protocols {args.protocols!r}: {model} runs the protocols "
                              f"{sorted(flat.PROTOCOLS)} and plan<seconds>")
        added, unchanged = simulate_flat_into(registry, model, args.units, args.seed, protocols,
                                              args.severity, move_s, points)
    else:
        config = load_fleet_config(args.fleet) if args.fleet else FleetConfig()
        timed = [design_protocol(designed_seconds(p), move_s, points=points) if is_designed(p) else p
                 for p in protocols]
        added, unchanged = simulate_into(registry, config, args.units, args.seed, timed,
                                         progress=sys.stderr.isatty())
    print(f"simulated {args.units} units into {registry.root}: {added} runs added, "
          f"{unchanged} unchanged ({time.perf_counter() - start:.1f} s)")
    return 0


def cmd_import(args: argparse.Namespace) -> int:
    registry = _registry(args, create=True)
    report = registry.import_paths([Path(p) for p in args.paths], column_map=args.csv_map,
                                   protocol=args.protocol)
    print(report.summary() + (f", marked as protocol {args.protocol!r}" if args.protocol else ""))
    return 0


def cmd_protocol(args: argparse.Namespace) -> int:
    if (args.protocol is None) == (not args.clear):
        raise AnytipError("give a protocol name or --clear, not both")
    records = _registry(args).set_protocol(args.target, None if args.clear else args.protocol)
    for r in records:
        mark = "(named by its file)" if r.protocol and not r.protocol_set else ""
        print(f"{r.run_id}: {r.protocol or '-'} {mark}".rstrip())
    return 0


def cmd_export(args: argparse.Namespace) -> int:
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise AnytipError(f"--out {out}: exists and is not a directory")
    paths = _registry(args).export(args.target, out, overwrite=args.force, format_version=args.format_version)
    for p in paths:
        print(p)
    return 0


def cmd_list(args: argparse.Namespace) -> int:
    records = _registry(args).list_runs(unit=args.unit, sensor_model=args.model)
    if not records:
        filters = (("unit", args.unit), ("sensor model", args.model))
        wanted = " and ".join(f"{k} {v!r}" for k, v in filters if v)
        print(f"no runs{' of ' + wanted if wanted else ''} in {_registry_path(args)}", file=sys.stderr)
        return 1
    _print_runs(records, args.json)
    if not args.json:
        _print_models(_registry(args).sensor_models(), records)
    return 0


def cmd_verify(args: argparse.Namespace) -> int:
    report = _registry(args).verify()
    for problem in report.problems():
        print(problem)
    print(f"{report.checked} runs checked: " + ("ok" if report.ok else f"{len(report.problems())} problems"))
    return 0 if report.ok else 1


def cmd_remove(args: argparse.Namespace) -> int:
    removed = _registry(args).remove(args.target)
    print(f"removed {len(removed)} runs: {', '.join(r.run_id for r in removed)}")
    return 0


def quickstart_spec() -> Path:
    """The main job's spec: experiments/quickstart.yaml of the current directory if there is one
    (a lab's own), else the one shipped with the package."""
    from anytip.rundir import builtin

    for folder in (Path.cwd() / "experiments", builtin("experiments")):
        if (folder / "quickstart.yaml").is_file():
            return folder / "quickstart.yaml"
    raise AnytipError("experiments/quickstart.yaml not found in the current directory or the package")


def cmd_run(args: argparse.Namespace) -> int:
    from anytip.runner import run_experiment

    run_experiment(args.spec, _registry_path(args), out=args.out, overrides=args.set,
                   progress=sys.stderr.isatty(), force=args.force)
    return 0


def cmd_report(args: argparse.Namespace) -> int:
    from anytip.runner import pool_runs, rewrite_report

    if args.out is None:
        if len(args.run_dir) > 1:
            raise AnytipError("several run directories pool into one report: give --out DIR")
        print(f"wrote {rewrite_report(args.run_dir[0])}")
        return 0
    print(f"wrote {pool_runs(args.run_dir, args.out, args.force)}")
    return 0


def cmd_compare(args: argparse.Namespace) -> int:
    from anytip.runner import compare_runs

    labelled = []
    for item in args.runs:
        label, sep, rest = item.partition("=")
        paths, _, method = rest.partition("#")
        dirs = paths.split(",")
        if not sep or not label or not all(dirs):
            raise AnytipError(f"{item!r}: give each entry as LABEL=RUN_DIR[,RUN_DIR...][#METHOD]")
        labelled.append((label, dirs, method or None))
    print(f"wrote {compare_runs(labelled, args.out, args.force, args.title)}")
    return 0


def cmd_calibrate(args: argparse.Namespace) -> int:
    from anytip.calibrate import calibrate_unit

    if args.plan is not None:
        return write_plan(args)
    if args.sensor_model is not None:
        raise AnytipError("--sensor-model is for --plan; a calibration takes the unit's model from its runs")
    if args.plan_points is not None:
        raise AnytipError("--plan-points is for --plan; a calibration reads the plan the unit's runs hold")
    missing = [f"--{k}" for k in ("model", "unit") if getattr(args, k) is None]
    if missing:
        raise AnytipError(f"calibrate needs {' and '.join(missing)} (or --plan SECONDS to write a plan)")
    out = Path(args.out)
    if (out / "model.safetensors").exists() and not args.force:
        raise AnytipError(f"--out {out}: already holds a calibrated model; choose another or pass --force")
    registry = _registry(args)
    r = calibrate_unit(args.model, args.unit, registry, out, args.budget_samples,
                       args.budget_seconds, args.adapter, args.seed, args.interval_level or None, args.method,
                       args.ordinary_use, args.factor_from, args.plan_strategy, args.use_log)
    for note in r.notes:
        print(note, file=sys.stderr if note.startswith("warning") else sys.stdout)
    units = _output_units(registry, r.unit)
    if r.response_check is not None:
        return _print_response(r, units)
    print(f"calibrated {r.unit}: {r.calib_samples} labeled samples ({r.calib_seconds:.1f} robot-s), "
          f"{r.unlabeled_samples} unlabeled{f', prior {r.prior:g}' if r.calib_samples else ''}; "
          f"folded model in {r.path / 'model.safetensors'}")
    if r.check is not None:
        print(_check_line(r.check))
    if r.own_check is not None:
        own = r.own_check
        fleet = ""
        if "over_fleet" in own:
            fleet = (f" (the fleet's validation units: {own['fleet_validation_mse']:.3g} on their test "
                     f"patches at this budget, {own['over_fleet']:.2f}x; not the same rows)")
        print(f"own check: standardised MSE {own['standardised_mse']:.3g} on the plan's {own['presses']} "
              f"presses, each predicted by the adapter refitted without its fold ({own['folds']} "
              f"folds){fleet}")
        if "over_validation" in own:
            val = ", ".join(f"{v:.3g}" for v in own["validation_units_mse"])
            print(f"  the shared model's validation units, checked the same way: {val}; this unit is "
                  f"{own['over_validation']:.2f}x the worst of them{' (ALARM)' if own['alarm'] else ''}")
    if r.intervals is not None:
        _print_intervals(r.intervals, units)
    elif args.interval_level and r.calib_samples:
        print("no intervals: the plan holds fewer presses than the folds needed to cross-fit them")
    took = f"; its own check and intervals (fold fits) in {r.check_s:.1f} s" if r.own_check else ""
    print(f"fitted and folded in {_seconds(r)}{took}")
    return 0


def _check_line(check: dict[str, Any]) -> str:
    """A calibrated model's RMSE on the unit's other runs, one phrase."""
    figures = ", ".join(f"{key.removesuffix('_rmse_n').removesuffix('_rmse_rad').removesuffix('_rmse')} "
                        f"RMSE {check[key]:.4g} {unit}" for key, unit in check["units"].items())
    return f"on the unit's other runs ({check['rows']} rows, not used to calibrate): {figures}"


def _print_response(r: Any, units: dict[str, str]) -> int:
    """A unit calibrated by response transfer, on the console (`units`: each output's, `_output_units`)."""
    own = r.response_check
    use = (f", {r.unlabeled_samples} unlabeled samples ({r.unlabeled_seconds:.1f} s of ordinary use, no rig "
           "time)") if r.unlabeled_samples else ""
    print(f"calibrated {r.unit} by response transfer: {r.calib_samples} labeled samples "
          f"({r.calib_seconds:.1f} robot-s, {own['presses']} presses){use}; its own network in "
          f"{r.path / 'model.safetensors'}")
    if r.check is not None:
        print(_check_line(r.check))
    if "residual_pa" not in own:  # label-free: no plan to check
        print(f"codes fitted, the training units' rows carried over and the unit's network trained in "
              f"{_seconds(r)}")
        return 0
    line = (f"own check: the plan's pressures lie {own['residual_pa']:.0f} Pa (RMS) from the unit's fitted "
            f"response; the training units' rows lie {own['fleet_noise_pa']:.0f} Pa from theirs")
    if "over_validation" in own:
        val = ", ".join(f"{v:.0f}" for v in own["validation_units_pa"])
        line += (f"\n  the benchmark's validation units at this budget: {val} Pa; this unit is "
                 f"{own['over_validation']:.2f}x the worst of them{' (ALARM)' if own['alarm'] else ''}")
    print(line)
    if r.intervals is not None:
        _print_intervals(r.intervals, units)
    print(f"codes fitted, the training units' rows carried over and the unit's network trained in "
          f"{_seconds(r)}")
    return 0


def _seconds(r: Any) -> str:
    """A calibration's fit-and-fold seconds with the speed of the core that spent them."""
    if r.core_gflops is None:
        return f"{r.wall_s:.1f} s"
    return (f"{r.wall_s:.1f} s, on a core that runs the reference float32 product at {r.core_gflops:.1f} "
            "GFLOP/s (core_gflops in calibration.json)")


def _output_units(registry: Registry, unit: str) -> dict[str, str]:
    """Each output's (label column's) SI unit, from the layout the registry records for `unit`'s sensor
    model (the fingertip's: fx, fy, fz in N, theta, phi in rad); empty where it records none."""
    from anytip.data.runfile import parse_layout

    records = registry.list_runs(unit=unit)
    layout = registry.sensor_models().get(records[0].sensor_model) if records else None
    if layout is None:
        return {}
    return {c: t.unit for t in parse_layout(layout)[1].values() for c in t.components}


def _print_intervals(bands: dict[str, Any], units: dict[str, str]) -> None:
    """A calibrated unit's intervals (`calibrate.plan_intervals`) on the console, each half-width in its
    output's unit (`units`, `_output_units`)."""
    half = ", ".join(f"{k} +-{v:.3g}{f' {units[k]}' if k in units else ''}"
                     for k, v in bands["halfwidth"].items())
    source = (f"{bands['folds']} press folds, {bands['rows']} out-of-fold rows" if bands["folds"] is not None
              else f"residuals on its {bands['rows']} rows, which also trained the network")
    print(f"{bands['level']:.0%} intervals from the plan ({source}): {half}")
    if "fleet_factor" in bands:
        factor = ", ".join(f"{k} x{v:.2f}" for k, v in bands["fleet_factor"].items())
        print(f"  the plan's own half-widths times the fleet factor the benchmark's validation (and factor) "
              f"units learnt, with its margin where one was recorded: {factor}")
    if "coverage_on_other_runs" in bands:
        cover = ", ".join(f"{k} {v:.3f}" for k, v in bands["coverage_on_other_runs"].items())
        print(f"  share of the unit's other runs inside them: {cover}")


def write_plan(args: argparse.Namespace) -> int:
    """`anytip calibrate --plan SECONDS --out plan.csv`: the designed calibration as waypoints."""
    from anytip.data.plans import RigTiming, designed_plan_csv
    from anytip.sensor import flat

    given = [f"--{k.replace('_', '-')}" for k in ("model", "unit", "budget_samples", "budget_seconds")
             if getattr(args, k) is not None]
    if given:
        raise AnytipError(f"--plan writes a plan for the rig; it takes no {', '.join(given)}")
    out = Path(args.out)
    if out.exists() and not args.force:
        raise AnytipError(f"--out {out}: exists; choose another or pass --force")
    model = _sensor_model(args, "plans are designed for")
    if model in flat.DESIGNS:
        if args.remount_s is not None:
            raise AnytipError(f"--remount-s: {model} is calibrated in one orientation, with no re-mount")
        rig, timing = RigTiming(args.move_s), f"moves {args.move_s:g} s"
    else:
        remount_s = 30.0 if args.remount_s is None else args.remount_s
        rig, timing = RigTiming(args.move_s, remount_s), f"moves {args.move_s:g} s, re-mounts {remount_s:g} s"
    flat_model = model if model in flat.DESIGNS else None
    text, seconds, what = designed_plan_csv(args.plan, rig, args.seed or 0, flat_model, args.plan_points)
    write_text(out, text)
    print(f"wrote {out}: {what}; {text.count(chr(10)) - 1} waypoints, "
          f"{seconds:.1f} s of robot time ({timing})")
    return 0


def cmd_export_model(args: argparse.Namespace) -> int:
    """`anytip export MODEL --format F --out DIR`: export one unit and verify it."""
    from anytip.data.registry import Registry
    from anytip.deploy.export import FORMATS, export_model

    root = _registry_path(args)
    registry = Registry(root, create=False) if (root / "catalog.sqlite").is_file() else None
    out_root = Path(args.out)
    if out_root.exists() and not out_root.is_dir():
        raise AnytipError(f"--out {out_root}: exists and is not a directory")
    formats = [f for f in FORMATS if f != "model"] if args.format == "all" else [args.format]
    targets = {fmt: out_root / fmt if len(formats) > 1 else out_root for fmt in formats}
    taken = [str(out) for out in targets.values() if (out / "verification.json").exists()]
    if taken and not args.force:
        raise AnytipError(f"--out {taken[0]}: already holds an export; choose another or pass --force")
    held_out = args.held_out or "auto"
    failed = 0
    for fmt, out in targets.items():
        r = export_model(args.model, fmt, out, unit=args.unit, registry=registry, rows=args.rows,
                         embedded_checks=not args.no_embedded, held_out=held_out)
        failed += not r["passed"]
        print(f"{fmt}: unit {r['unit']} -> {out} ({', '.join(r['files'])}); verification "
              f"{'passed' if r['passed'] else 'FAILED'} on {r['reference']['source']} rows, "
              f"report {out / 'verification.json'}")
        if r["reference"].get("warning"):
            print(f"warning: {r['reference']['warning']}", file=sys.stderr)
    return 1 if failed else 0


def cmd_search(args: argparse.Namespace) -> int:
    """`anytip search SPEC`: `anytip run` for a search spec, with the study's storage and workers."""
    from anytip.runner import run_experiment

    overrides = list(args.set)
    if args.storage:
        overrides.append(f"options.storage={args.storage}")
    if args.workers:
        overrides.append(f"options.workers={args.workers}")
    run_experiment(args.spec, _registry_path(args), out=args.out, overrides=overrides,
                   progress=sys.stderr.isatty(), force=args.force)
    return 0


def cmd_main_job(args: argparse.Namespace) -> int:
    """The README's main job: the quickstart experiment (simulates a fleet into an empty registry)."""
    ns = argparse.Namespace(spec=str(quickstart_spec()), registry=args.registry, out=None, set=[],
                            force=False)
    return cmd_run(ns)


def _add_registry_opt(p: argparse.ArgumentParser, top: bool = False) -> None:
    # Sub-commands suppress the default so `anytip --registry X data list` keeps X.
    p.add_argument("--registry", default=None if top else argparse.SUPPRESS,
                   help="registry directory (default: $ANYTIP_REGISTRY or ./data/registry)")


def _add_spec_parser(sub, name: str, help_: str, spec_help: str,
                     func: Callable[[argparse.Namespace], int]) -> argparse.ArgumentParser:
    """A sub-command that runs a spec: SPEC, --registry, --out, --set."""
    p = sub.add_parser(name, help=help_)
    _add_registry_opt(p)
    p.add_argument("spec", help=spec_help)
    p.add_argument("--out", default=None, help="run directory (default runs/<spec>/<UTC time>/)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a spec key, e.g. --set training.epochs=3 (repeatable)")
    p.add_argument("--force", action="store_true", help="overwrite a run already in --out")
    p.set_defaults(func=func)
    return p


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="anytip", description=__doc__)
    _add_registry_opt(parser, top=True)
    parser.set_defaults(func=cmd_main_job)
    sub = parser.add_subparsers(dest="command")
    _add_spec_parser(sub, "run", "run an experiment spec", "experiments/<name>.yaml", cmd_run)
    search = _add_spec_parser(sub, "search", "run an architecture search spec (an Optuna study)",
                              "experiments/search.yaml or another `pipeline: search` spec", cmd_search)
    search.add_argument("--storage", default=None,
                        help="Optuna storage URL, e.g. postgresql://user@host/db (default: "
                             "$ANYTIP_SEARCH_STORAGE, else sqlite in the run directory); give the "
                             "password through $ANYTIP_SEARCH_STORAGE or PGPASSWORD, not here")
    search.add_argument("--workers", type=int, default=None, help="processes sharing the study here")
    rep = sub.add_parser("report", help="write a finished run's report again from its recorded results, "
                                        "or pool several runs' held-out units (folds, seeds) into one report")
    rep.add_argument("run_dir", nargs="+", help="a run directory (config.yaml, metrics.json, "
                                                "provenance.json); with --out, several runs of one "
                                                "cross_sensor benchmark")
    rep.add_argument("--out", default=None, help="pool the runs into this new run directory and write its "
                                                 "report")
    rep.add_argument("--force", action="store_true", help="overwrite a pooled report already in --out")
    rep.set_defaults(func=cmd_report)
    cmp = sub.add_parser("compare", help="finished cross_sensor runs side by side (severities, fleets, "
                                         "recipes, ablations): per budget, a table and a figure")
    cmp.add_argument("runs", nargs="+", metavar="LABEL=RUN_DIR[,RUN_DIR...][#METHOD]",
                     help="a label and a run directory, or several whose held-out units pool (folds, or a "
                          "run and its rescoring at other budgets), comma separated: their validation units' "
                          "choice per budget, or the method named after #")
    cmp.add_argument("--out", required=True, help="where the comparison's report is written")
    cmp.add_argument("--force", action="store_true", help="overwrite a comparison already in --out")
    cmp.add_argument("--title", default=None, help="the report's heading (default: Comparison of N runs)")
    cmp.set_defaults(func=cmd_compare)
    cal = sub.add_parser("calibrate", help="fit a new unit's adapter and save its folded model")
    _add_registry_opt(cal)
    cal.add_argument("--model", help="a cross_sensor run directory, or a shared model .safetensors file")
    cal.add_argument("--unit", help="the unit's id in the registry")
    cal.add_argument("--plan", type=float, default=None, metavar="SECONDS",
                     help="write the fingertip rig's designed calibration of SECONDS robot-seconds to "
                          "--out as robot waypoints (CSV, docs/cross_sensor.md) instead of calibrating; "
                          "with --sensor-model, a flat design's as stage waypoints")
    cal.add_argument("--move-s", type=float, default=2.0,
                     help="with --plan: seconds per move between presses")
    cal.add_argument("--remount-s", type=float, default=None,
                     help="with --plan: seconds per change of orientation (default 30)")
    cal.add_argument("--sensor-model", default=None,
                     help="with --plan: the sensor model the plan is for (default: the fingertip, "
                          "fingertip-8baro-r10; also edge-4baro, pad-16baro)")
    cal.add_argument("--plan-points", choices=("halton", "random"), default=None,
                     help="with --plan: its points drawn at random (random, a flat design's default) or "
                          "spread by a low-discrepancy sequence (halton, the fingertip's default: its "
                          "patches in the R2 order, force levels in turn); research log entries 212-216")
    budget = cal.add_mutually_exclusive_group()
    budget.add_argument("--budget-samples", type=int, default=None,
                        help="labeled rows from the start of the calibration stream "
                             "(default 1000; 0: label-free)")
    budget.add_argument("--budget-seconds", type=float, default=None,
                        help="robot-seconds of calibration: whole presses chosen as the shared "
                             "model's benchmark chose them, or, for a model benchmarked in samples, "
                             "the rows within this many robot-seconds of the stream")
    cal.add_argument("--adapter", default=None,
                     help="adapter kind of the run's shared models (<kind>_episodic: trained episodically)")
    cal.add_argument("--seed", type=int, default=None,
                     help="which seed's shared model of the run (with --plan: the press points' draw)")
    cal.add_argument("--out", required=True,
                     help="directory for the folded per-unit model (with --plan: the CSV file)")
    cal.add_argument("--interval-level", type=float, default=0.9,
                     help="nominal coverage of the unit's intervals from its own plan (default 0.9; "
                          "0: none); needs a plan of at least 5 presses")
    cal.add_argument("--method", choices=["auto", "adapter", "response"], default="auto",
                     help="adapter: fold the shared model's adapter; response: response transfer (a run "
                          "with a response model); auto (default): response where the run's validation "
                          "units scored it lower at this budget")
    cal.add_argument("--ordinary-use", type=float, default=0.0, metavar="SECONDS",
                     help="also read SECONDS (at most 600) of contact of the unit's ordinary use, whole "
                          "presses of its calibration stream with their labels unread, and fit its codes "
                          "from them and the plan together (with --budget-seconds 0, from them alone); "
                          "response transfer only (research log entries 44-46)")
    cal.add_argument("--factor-from", nargs="+", default=[], metavar="RUN",
                     help="other runs of the same benchmark (a registry's other unit folds): their response "
                          "models' validation units learn the intervals' fleet factor and margin with this "
                          "run's, all but the unit calibrated; response transfer only (research log "
                          "entry 53); list every other fold's run with --use-log (entry 199)")
    cal.add_argument("--plan-strategy", default=None, metavar="STRATEGY",
                     help="the press selection response transfer calibrates by (cover, cover_informative, "
                          "...), where a choice was made on more validation units than the run's; default: "
                          "the one the run's validation units scored lowest at this budget (research log "
                          "entry 100); or designed: the unit's runs of the designed calibration of the "
                          "budget's seconds (plan<seconds>, from --plan), which a unit whose runs are that "
                          "alone gets by default")
    cal.add_argument("--use-log", nargs="+", default=[], metavar="FILE",
                     help="ordinary-use logs of the unit (pressures alone, docs/calibration_format.md), read "
                          "with --ordinary-use instead of its runs: contacts found from the pressures")
    cal.add_argument("--force", action="store_true", help="overwrite a model already in --out")
    cal.set_defaults(func=cmd_calibrate)
    exp = sub.add_parser("export",
                         help="export one unit of a model (ONNX, C, int8 C, firmware struct), verified")
    _add_registry_opt(exp)
    exp.add_argument("model", help="model .safetensors or directory, or a firmware nets JSON to import")
    exp.add_argument("--format", required=True, choices=["onnx", "c", "c-int8", "firmware", "model", "all"],
                     help="what to write ('model': an anytip model file, e.g. of an imported firmware net)")
    exp.add_argument("--out", required=True, help="output directory (one sub-directory per format for 'all')")
    exp.add_argument("--unit", default=None, help="which unit of the model file (default: the first)")
    exp.add_argument("--rows", type=int, default=20000, help="reference rows to verify on (default 20000)")
    exp.add_argument("--force", action="store_true", help="overwrite an export already in --out")
    exp.add_argument("--held-out", default=None, metavar="RUN_DIR[:SEED]",
                     help="score RMSE on the rows this cross_sensor or baseline run held out from the "
                          "model (default: found from the model file's run directory or metadata)")
    exp.add_argument("--no-embedded", action="store_true",
                     help="skip the Cortex-M4F cross-compile and emulator measurements")
    exp.set_defaults(func=cmd_export_model)
    data = sub.add_parser("data", help="the registry of calibration runs")
    data_sub = data.add_subparsers(dest="verb", required=True)

    def verb(name: str, func: Callable[[argparse.Namespace], int], help_: str):
        p = data_sub.add_parser(name, help=help_)
        _add_registry_opt(p)
        p.set_defaults(func=func)
        return p

    p = verb("simulate", cmd_simulate, "simulate a fleet into the registry")
    p.add_argument("--fleet", help="fleet config YAML (default: the built-in default fleet)")
    p.add_argument("--units", type=int, default=8, help="units to simulate (default 8)")
    p.add_argument("--seed", type=int, default=0,
                   help="fleet seed (>= 0, default 0): the same seed gives the same units and runs")
    p.add_argument("--protocols", default="full,short",
                   help="comma-separated calibration protocols to run on each unit (default full,short)")
    p.add_argument("--sensor-model", default=None,
                   help="simulate this sensor model (default: the fingertip, fingertip-8baro-r10; "
                        "also edge-4baro, pad-16baro)")
    p.add_argument("--severity", type=float, default=1.0,
                   help="unit-to-unit variation of edge-4baro and pad-16baro, 1 = the default spread")
    p.add_argument("--move-s", type=float, default=None,
                   help="the rig's move before each press of a designed plan (plan<seconds>), in s "
                        "(default 2, as `anytip calibrate --plan` assumes)")
    p.add_argument("--plan-points", choices=("halton", "random"), default=None,
                   help="a designed plan's points, as `anytip calibrate --plan` takes them: drawn at "
                        "random (a flat design's default) or by a low-discrepancy sequence (halton, the "
                        "fingertip's default)")
    p = verb("import", cmd_import, "import interchange HDF5 files or CSV rig logs")
    p.add_argument("paths", nargs="+", help="run files (.h5, .hdf5), CSV logs (.csv) or directories of them")
    p.add_argument("--csv-map", default=None,
                   help="column map YAML for CSV logs (default: the built-in rig34 map)")
    p.add_argument("--protocol", default=None,
                   help="mark every imported run as run by this protocol, e.g. retest (a unit's test "
                        "session) or plan120 (the designed 120 s calibration); see `data protocol`")
    p = verb("export", cmd_export, "write a unit's or a run's interchange files")
    p.add_argument("target", metavar="UNIT_OR_RUN", help="a unit serial or a run id")
    p.add_argument("--out", required=True, help="directory for the <run_id>.h5 files")
    p.add_argument("--force", action="store_true", help="overwrite files already in --out")
    p.add_argument("--format-version", type=int, choices=[1, 2], default=None,
                   help="write the files as this interchange format version (default: each run's own, "
                        "so re-importing an export is recognised as the same run); 1 only for the "
                        "fingertip's targets")
    p = verb("list", cmd_list, "list runs (exit status 1 when none match)")
    p.add_argument("--json", action="store_true", help="one JSON object per run")
    p.add_argument("--unit", default=None, help="only the runs of this unit serial")
    p.add_argument("--model", default=None, help="only the runs of this sensor model")
    verb("verify", cmd_verify, "re-hash payloads, find missing and orphaned files")
    p = verb("protocol", cmd_protocol, "mark a unit's or a run's runs as run by a protocol "
             "(retest: its test session; plan<seconds>: a designed calibration)")
    p.add_argument("target", metavar="UNIT_OR_RUN", help="a unit serial or a run id")
    p.add_argument("protocol", nargs="?", default=None, help="the protocol name ([A-Za-z0-9._-]{1,64})")
    p.add_argument("--clear", action="store_true", help="remove the mark instead")
    p = verb("remove", cmd_remove, "remove a unit's or a run's runs")
    p.add_argument("target", metavar="UNIT_OR_RUN", help="a unit serial or a run id")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    if getattr(args, "registry", None) is None and os.environ.get("ANYTIP_REGISTRY"):
        args.registry = os.environ["ANYTIP_REGISTRY"]
    try:
        return args.func(args)
    except AnytipError as e:
        print(f"anytip: error: {mask_secrets(str(e))}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("anytip: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader went away (`anytip data list | head`): stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141


if __name__ == "__main__":
    sys.exit(main())
