"""`anytip run SPEC`: validate the spec, prepare the run directory, run its pipeline,
write metrics and provenance, print a summary.
"""

from __future__ import annotations

import importlib
import inspect
import time
from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import torch

from anytip import rundir
from anytip.config import ExperimentSpec, load_spec, public_config
from anytip.data.registry import Registry
from anytip.data.runfile import V1_LAYOUT
from anytip.errors import AnytipError
from anytip.pipelines.common import (
    Context,
    check_options,
    check_registry,
    recorded_metrics,
    resolve_device,
)
from anytip.report.cross_sensor import (
    budget_of,
    chosen_lines,
    comparison_report,
    in_seconds,
    is_reference,
    named_lines,
)
from anytip.report.markdown import table
from anytip.report.writer import Report
from anytip.train.metrics import target_key
from anytip.validation import mask_secrets


def fill_if_empty(spec: ExperimentSpec, registry: Registry, progress: bool) -> bool:
    """Simulate the spec's fleet into an empty registry when the spec asks for it."""
    if spec.simulate_if_empty is None or registry.list_runs():
        return False
    from anytip.data.simulated import simulate_into

    sim = spec.simulate_if_empty
    simulate_into(registry, spec.fleet, sim.units, sim.seed, sim.protocols, progress)
    print(f"simulated {sim.units} units into the empty registry {registry.root}")
    return True


def summarise(rows: list[dict[str, Any]], keys: Sequence[str] = ("force_rmse_n", "angle_rmse_rad")) -> str:
    """One screen: the mean of each target's RMSE (`keys`) per (method, split) group."""
    groups: dict[tuple, list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        groups[(r["method"], r.get("split", "-"))].append(r)
    keys = [k for k in keys if any(k in r for r in rows)]
    lines = [f"{'method':<24}{'split':<10}{'rows':>6}" + "".join(f"{k:>18}" for k in keys)]
    for (method, split), rs in sorted(groups.items()):
        means = [np.mean([r[k] for r in rs if k in r]) for k in keys]
        lines.append(f"{method:<24}{split:<10}{len(rs):>6}" + "".join(f"{m:>18.4g}" for m in means))
    return "\n".join(lines)


def run_experiment(spec_path: str | Path, registry: Registry | str | Path, out: str | Path | None = None,
                   overrides: list[str] | None = None, progress: bool = True, force: bool = False) -> Path:
    """Run one spec against `registry` (a Registry, or its directory: created only for a spec
    that simulates into an empty registry or a pipeline that reads none); returns the run
    directory.

    Everything a user can get wrong is checked before the run directory is made: the spec
    and its options, and whether the registry holds enough units. `out` must not hold a
    run already unless `force`.
    """
    spec = load_spec(spec_path, overrides)
    device = resolve_device(spec.device)
    module = importlib.import_module(f"anytip.pipelines.{spec.pipeline}")
    use = getattr(module, "REGISTRY", "required")  # "required", "optional" (any units) or "unused"
    if not isinstance(registry, Registry):
        registry = Registry(registry, create=spec.simulate_if_empty is not None or use == "unused")
    ctx = Context(spec, registry, Path(), device, progress)
    ctx.provenance["spec_file"] = str(spec_path)
    check_options(ctx, module)
    if out is not None:
        rundir.check_run_dir(Path(out), force)
    if spec.threads is not None:
        torch.set_num_threads(spec.threads)
    fill_if_empty(spec, registry, progress)
    if use == "required":
        need = module.min_units(ctx) if hasattr(module, "min_units") else 1
        fingertip_only = getattr(module, "FINGERTIP_ONLY", False)
        spec = ctx.spec = check_registry(spec, registry, need, str(spec_path), fingertip_only)
    run_dir = rundir.new_run_dir(spec.name, out, force=force)
    ctx.run_dir = run_dir
    rundir.write_config(run_dir, public_config(spec))
    ctx.provenance.update(overrides=[mask_secrets(o) for o in overrides or []], seeds=spec.all_seeds,
                          code=rundir.code_version(), machine=rundir.machine(), device=str(device))
    start = time.perf_counter()
    rows = module.run(ctx)
    ctx.provenance["wall_s"] = round(time.perf_counter() - start, 2)
    ctx.provenance.update(rundir.peak_memory())
    keys = [target_key(name) for name in ctx.provenance.get("targets", V1_LAYOUT)]
    rundir.write_metrics(run_dir, rows, keys, spec=spec.name, pipeline=spec.pipeline)
    rundir.write_json(run_dir / "provenance.json", ctx.provenance)
    if hasattr(module, "summarise"):  # a pipeline's own screen, given the targets where it takes them
        takes = "targets" in inspect.signature(module.summarise).parameters
        print(module.summarise(rows, ctx.provenance.get("targets")) if takes else module.summarise(rows))
    else:
        print(summarise(rows, keys))
    print(f"run directory: {run_dir}  (report: {run_dir / 'report.md'})")
    return run_dir


Finished = tuple[ExperimentSpec, dict[str, Any], list[dict[str, Any]]]  # a run's spec, provenance and rows


def finished_run(run_dir: str | Path) -> Finished:
    """What a finished run recorded: its spec (config.yaml), provenance and result rows; a missing
    or malformed file is refused by name."""
    run_dir = Path(run_dir)
    for name in ("config.yaml", "metrics.json", "provenance.json"):
        if not (run_dir / name).is_file():
            raise AnytipError(f"{run_dir}: not a finished run directory (no {name})")
    spec = load_spec(run_dir / "config.yaml")
    provenance = rundir.read_json(run_dir / "provenance.json")
    metrics = rundir.read_json(run_dir / "metrics.json")
    rows = metrics.get("results") if isinstance(metrics, dict) else None
    if not isinstance(rows, list) or not all(isinstance(r, dict) for r in rows):
        raise AnytipError(f"{run_dir / 'metrics.json'}: no 'results' list of rows")
    missing = next((k for r in rows for k in rundir.ROW_KEYS if k not in r), None)
    if missing is not None:
        raise AnytipError(f"{run_dir / 'metrics.json'}: a result row lacks {missing!r}")
    if not isinstance(provenance, dict):
        raise AnytipError(f"{run_dir / 'provenance.json'}: not a JSON object")
    return spec, provenance, rows


def rewrite_report(run_dir: str | Path) -> Path:
    """Write a finished run's report again from what the run recorded (its config.yaml,
    metrics.json and provenance.json), with this version's report writer: no training, no
    registry. For pipelines that provide `report(ctx, rows)`; others are refused by name."""
    run_dir = Path(run_dir)
    spec, provenance, rows = finished_run(run_dir)
    module = importlib.import_module(f"anytip.pipelines.{spec.pipeline}")
    if not hasattr(module, "report"):
        raise AnytipError(f"{run_dir}: pipeline {spec.pipeline!r} cannot rewrite its report from "
                          "recorded results; run the spec again")
    ctx = Context(spec, None, run_dir, torch.device("cpu"), False, provenance)  # type: ignore[arg-type]
    module.report(ctx, rows)
    return run_dir / "report.md"


POOLABLE = ("cross_sensor",)  # pipelines whose rows are held-out units scored against their own references
COMPARISON = "comparison.json"  # what `compare_runs` writes beside its report


def pool_runs(run_dirs: Sequence[str | Path], out: str | Path, force: bool = False) -> Path:
    """Several finished runs of one benchmark (its unit folds or seeds, run apart) as one run
    directory `out` whose report pools their held-out units, written with the report writer a run
    uses: ratios per distinct unit over every run's units, and each budget's method chosen by the
    mean validation loss over every run's seeds. Nothing is trained or read beyond the runs' own
    files. The runs must share a pipeline that scores held-out units (`POOLABLE`), a sensor model
    and its targets; a (unit, seed) scored in two runs (a run and its rescoring) is refused, as is
    pooling fewer than two runs. Where the runs' specs differ beyond their seeds, the report lists
    how. `out`'s config.yaml is the first run's spec with every run's seeds."""
    dirs = [Path(d) for d in run_dirs]
    if len(dirs) < 2:
        raise AnytipError("pooling needs at least two run directories")
    if len({d.resolve() for d in dirs}) < len(dirs):
        raise AnytipError("a run directory is named twice; each run is pooled once")
    out = Path(out)
    _refuse_out_among(out, dirs)
    runs, rows = read_pool(dirs)
    first_spec, first_prov, _ = runs[0]
    rundir.check_run_dir(out, force)
    out.mkdir(parents=True, exist_ok=True)
    base = public_config(first_spec)
    seeds = sorted({int(r["seed"]) for r in rows})
    rundir.write_config(out, {**base, "seeds": seeds})
    labels = _run_labels(dirs)
    provenance = {k: first_prov.get(k) for k in ("sensor_model", "targets", "extra_units") if k in first_prov}
    provenance.update(
        units=sorted({str(u) for _, p, _ in runs for u in p.get("units", [])}),
        cross_sensor={f"{label}/{key}": {**p["cross_sensor"][key], "val_loss": losses}
                      for label, d, (spec, p, _) in zip(labels, dirs, runs, strict=True)
                      for key, losses in _validation_losses(d, spec, p).items()},
        pooled_from=[{"run": str(d), "label": label, "seeds": sorted({int(r["seed"]) for r in rs}),
                      "held_out_units": len({r["unit"] for r in rs if r["method"] == "per_unit"}),
                      "selection_content_hash": p.get("selection_content_hash"), "code": p.get("code"),
                      "differs": _config_differences(base, public_config(spec))}
                     for d, label, (spec, p, rs) in zip(dirs, labels, runs, strict=True)],
        code=rundir.code_version())
    keys = [target_key(name) for name in provenance.get("targets") or []]
    rundir.write_metrics(out, rows, *([keys] if keys else []), spec=first_spec.name,
                         pipeline=first_spec.pipeline)
    rundir.write_json(out / "provenance.json", provenance)
    return rewrite_report(out)


def read_pool(dirs: Sequence[str | Path], method: str | None = None
              ) -> tuple[list[Finished], list[dict[str, Any]]]:
    """Finished runs that pool (`finished_run` of each) and their rows together (`_pooled_rows`):
    each of a pipeline in `POOLABLE`, all of one sensor model and its targets. With `method` named
    (a comparison entry's), only its rows and the references pool where the runs hold it, so the
    runs' other methods may score the same budgets."""
    dirs = [Path(d) for d in dirs]
    runs = [finished_run(d) for d in dirs]
    for d, (spec, _, _) in zip(dirs, runs, strict=True):
        if spec.pipeline not in POOLABLE:
            raise AnytipError(f"{d}: pipeline {spec.pipeline!r} cannot be pooled or compared "
                              f"(only {', '.join(POOLABLE)})")
    _one_sensor_model([(str(d), prov) for d, (_, prov, _) in zip(dirs, runs, strict=True)])
    rows = [r for _, _, r in runs]
    if method is not None and any(r["method"] == method for rs in rows for r in rs):
        rows = [[r for r in rs if r["method"] == method or is_reference(r["method"])] for rs in rows]
    return runs, _pooled_rows(dirs, rows)


def _one_sensor_model(named: list[tuple[str, dict[str, Any]]]) -> None:
    """Refuse (name, provenance) pairs whose sensor model or targets differ from the first's: only
    runs of one sensor model pool or compare."""
    first_name, first = named[0]
    for name, prov in named[1:]:
        for key in ("sensor_model", "targets"):
            if prov.get(key) != first.get(key):
                raise AnytipError(f"{name}: its {key} {prov.get(key)!r} differs from {first_name}'s "
                                  f"{first.get(key)!r}; only runs of one sensor model pool or compare")


class _Scored(NamedTuple):
    """What one run holds of one held-out (unit, seed): its per-unit reference rows in method order,
    and each (method, budget) scored."""

    run: Path
    references: list[dict[str, Any]]
    scored: set[tuple[str, float]]


def _pooled_rows(dirs: list[Path], rows_by_run: list[list[dict[str, Any]]]) -> list[dict[str, Any]]:
    """Every run's rows, each marked with its run (`pooled_run`: the index in `dirs`). A held-out
    (unit, seed) that two runs score pools only where they measured it apart (`_scored_apart`: the
    same per-unit references, no method at one budget in both; a run and its rescoring at other
    budgets), its references then kept once, from the first run; otherwise it is refused, as one
    unit's draw pooled twice."""
    seen: dict[tuple[str, int], _Scored] = {}
    out = []
    for i, rows in enumerate(rows_by_run):
        mine: dict[tuple[str, int], list[dict[str, Any]]] = defaultdict(list)
        for r in rows:
            mine[_unit_seed(r)].append(r)
        repeated = set()
        for key, rs in sorted(mine.items()):
            refs = sorted((r for r in rs if is_reference(r["method"])), key=lambda r: r["method"])
            scored = {(r["method"], budget_of(r)) for r in rs if not is_reference(r["method"])}
            now = _Scored(dirs[i], refs, scored)
            if key in seen:
                _scored_apart(key, seen[key], now)
                seen[key].scored.update(now.scored)
                repeated.add(key)
            else:
                seen[key] = now
        out += [{**r, "pooled_run": i} for r in rows
                if not (is_reference(r["method"]) and _unit_seed(r) in repeated)]
    return out


def _unit_seed(row: dict[str, Any]) -> tuple[str, int]:
    """A result row's held-out (unit, seed)."""
    return str(row["unit"]), int(row["seed"])


def _scored_apart(key: tuple[str, int], a: _Scored, b: _Scored) -> None:
    """Refuse one held-out (unit, seed) in two runs unless their references are equal row for row
    and no method is scored at one budget in both."""
    where = f"unit {key[0]}, seed {key[1]} is scored in both {a.run} and {b.run}"
    both = sorted(a.scored & b.scored)
    if both:
        raise AnytipError(f"{where}, {both[0][0]} at budget {both[0][1]:g} in each: pool folds or seeds "
                          "that hold out different units, or runs of other budgets or methods (report a "
                          "run and its rescoring at the same budgets apart)")
    if a.references != b.references:
        raise AnytipError(f"{where}, against per-unit references that differ "
                          f"({_first_difference(a.references, b.references)}): runs pool one unit only "
                          "where they share its reference")


def _first_difference(a: list[dict[str, Any]], b: list[dict[str, Any]]) -> str:
    """The first of two reference row lists' differences, as text: their methods, or a key and both
    values."""
    if [r["method"] for r in a] != [r["method"] for r in b]:
        return f"methods {[r['method'] for r in a]} against {[r['method'] for r in b]}"
    ra, rb = next((ra, rb) for ra, rb in zip(a, b, strict=True) if ra != rb)
    k = next(k for k in sorted(set(ra) | set(rb)) if ra.get(k) != rb.get(k))
    return f"{ra['method']} {k}: {ra.get(k)!r} against {rb.get(k)!r}"


def _refuse_out_among(out: Path, dirs: Sequence[Path]) -> None:
    """Refuse an output directory that is one of the runs read: their own files are never replaced."""
    if out.resolve() in {d.resolve() for d in dirs}:
        raise AnytipError(f"--out {out}: is one of the runs read; choose another directory")


def _run_labels(dirs: list[Path]) -> list[str]:
    """A short name per run (its directory's name, with its position where two share one)."""
    names = [d.name for d in dirs]
    return [n if names.count(n) == 1 else f"{i}:{n}" for i, n in enumerate(names)]


def _config_differences(base: dict[str, Any], other: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    """{dotted key: other's value} where `other` differs from `base`, seeds aside."""
    diff: dict[str, Any] = {}
    for key in sorted(set(base) | set(other)):
        name = f"{prefix}{key}"
        a, b = base.get(key), other.get(key)
        if name == "seeds" or a == b:
            continue
        if isinstance(a, dict) and isinstance(b, dict):
            diff.update(_config_differences(a, b, f"{name}."))
        else:
            diff[name] = b
    return diff


def compare_runs(labelled: Sequence[tuple[str, Sequence[str | Path], str | None]], out: str | Path,
                 force: bool = False, title: str | None = None) -> Path:
    """Finished runs of one sensor model side by side in `out` (a report, its figure and
    `comparison.json`). Each entry is (label, runs, method): one run, or several whose held-out units
    pool (`read_pool`: a benchmark's folds), and either None, for each budget's method as the runs'
    own validation units chose it (`report.cross_sensor.chosen_lines`, validation loss averaged over
    the runs' seeds), or the method named. Runs of other fleets, severities or recipes compare, and
    one run's methods (an ablation); nothing is trained or read beyond the runs' own files."""
    if len(labelled) < 2:
        raise AnytipError("a comparison needs at least two LABEL=RUN_DIR")
    labels = [label for label, *_ in labelled]
    if len(set(labels)) < len(labels) or not all(labels):
        raise AnytipError(f"labels must be distinct and non-empty, got {labels}")
    out = Path(out)
    _refuse_out_among(out, [Path(d) for _, dirs, _ in labelled for d in dirs])
    if (out / "metrics.json").exists():
        raise AnytipError(f"--out {out}: holds a finished run, whose report.md a comparison would replace; "
                          "choose another directory")
    if (out / COMPARISON).exists() and not force:
        raise AnytipError(f"{out}: already holds a comparison ({COMPARISON}); choose another --out or "
                          "pass --force")
    pools = {label: read_pool(dirs, method) for label, dirs, method in labelled}
    _one_sensor_model([(label, runs[0][1]) for label, (runs, _) in pools.items()])
    first = pools[labels[0]][0][0][1]
    if len({in_seconds(rows) for _, rows in pools.values()}) > 1:
        raise AnytipError("some runs budget in robot seconds and others in labeled samples; compare like "
                          "with like")
    metrics = recorded_metrics(first.get("targets"))
    groups = {label: _compared_lines(*pools[label], method, metrics, dirs)
              for label, dirs, method in labelled}
    out.mkdir(parents=True, exist_ok=True)
    named = [[label, "<br>".join(f"`{d}`" for d in dirs),
              f"`{method}`" if method else "chosen on validation units"] for label, dirs, method in labelled]
    report = Report(out).add(f"# {title or f'Comparison of {len(labelled)} runs'}\n",
                             table(["label", "runs", "method"], named) + "\n")
    comparison_report(report, groups, in_seconds(pools[labels[0]][1]), metrics).write()
    rundir.write_json(out / COMPARISON, {
        "runs": {label: {"runs": [str(d) for d in dirs], "method": m} for label, dirs, m in labelled},
        "lines": groups, "code": rundir.code_version()})
    return out / "report.md"


def _compared_lines(runs: list[Finished], rows: list[dict[str, Any]], method: str | None,
                    metrics: Sequence[Any],
                    dirs: Sequence[str | Path]) -> list[dict[str, Any]]:
    """One comparison entry's lines from its runs (`read_pool`): the method named, or each budget's
    validation choice over the runs' seeds."""
    if method is not None:
        return named_lines(rows, method, metrics, ", ".join(map(str, dirs)))
    val_loss = {f"{i}/{k}": losses for i, (d, (spec, prov, _)) in enumerate(zip(dirs, runs, strict=True))
                for k, losses in _validation_losses(d, spec, prov).items()}
    if not any(val_loss.values()):
        raise AnytipError(f"{', '.join(map(str, dirs))}: no validation losses recorded (provenance.json "
                          "cross_sensor.*.val_loss, or the shared models' metadata): no method was chosen on "
                          "validation units; name one after #")
    return chosen_lines(rows, val_loss, metrics)


def _validation_losses(run_dir: str | Path, spec: ExperimentSpec, provenance: dict[str, Any]
                       ) -> dict[str, dict[str, dict[str, float]]]:
    """A finished cross_sensor run's validation losses per seed (`cross_sensor.recorded_val_losses`)."""
    from anytip.pipelines.cross_sensor import recorded_val_losses

    ctx = Context(spec, None, Path(run_dir), torch.device("cpu"), False, provenance)  # type: ignore[arg-type]
    return recorded_val_losses(ctx)
