"""Label-free whitening: does decorrelating a unit's barometers undo how units differ?

The benchmark's label-free method (`adapted:input_stats`) standardises each barometer of a
unit by the mean and spread of its first `unlabeled_s` seconds of pressures. Entry 6 of the
research log found that units differ mostly in how one contact maps to all barometers
together, which a per-barometer scale cannot undo. This script tests the next label-free
step: each unit's pressures whitened by the correlation of those same unlabeled seconds (ZCA:
x -> C^-1/2 (x - m) / s, C shrunk toward the identity by `--shrink`), for training and held-out
units alike. A pooled shared model (`none`) is trained on the whitened training units with the
run's recipe and scored zero-shot on the run's held-out units, against the run's own
`adapted:input_stats` rows and per-unit references.

    python scripts/label_free_whitening.py RUN_DIR --registry data/fleet24 [--shrink 0.0]
        [--seeds 0 1] [--out FILE.md]
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import torch

from anytip.config import load_spec
from anytip.data.arrays import FleetArrays
from anytip.data.calibration import calibration_stream
from anytip.data.plans import Budget
from anytip.data.registry import Registry
from anytip.pipelines.common import Context, load
from anytip.pipelines.cross_sensor import adapted_rows, min_units, prepare, shared_shape
from anytip.pipelines.cross_sensor_options import Options, parse_options
from anytip.pipelines.run_diagnostic import diagnose, diagnostic_parser
from anytip.report.cross_sensor import mean_interval
from anytip.train.adapt import train_shared
from anytip.train.shared_split import SeedData


def whitened(arrays: FleetArrays, opts: Options, shrink: float, sd: SeedData) -> FleetArrays:
    """A copy of `arrays` whose pressures are each unit's whitened pressures (dimensionless):
    standardised and decorrelated by the statistics of its first `unlabeled_s` seconds (of the
    stream `sd` gives a validation or held-out unit: never a row of its test patches)."""
    p = arrays.pressure.astype(np.float64)
    for i, unit in enumerate(arrays.units):
        stream = sd.evals[unit].stream if unit in sd.evals else calibration_stream(
            arrays, unit, opts.calibration_protocol, interleave=opts.calibration_interleave)
        x = p[stream.unlabeled(opts.unlabeled_s)]
        m, s = x.mean(0), np.maximum(x.std(0), 1e-9)
        corr = (1 - shrink) * np.corrcoef(((x - m) / s).T) + shrink * np.eye(x.shape[1])
        w, v = np.linalg.eigh(corr)
        inv_sqrt = (v * np.clip(w, 1e-6, None) ** -0.5) @ v.T
        mine = arrays.unit == i
        p[mine] = ((p[mine] - m) / s) @ inv_sqrt.T
    return dataclasses.replace(arrays, pressure=p.astype(np.float32))


def seed_lines(run: Path, registry: str, seed: int, shrink: float) -> list[dict]:
    """Per held-out unit of `seed`: force and angle ratios to its reference, whitened and with
    the run's input statistics."""
    spec = load_spec(run / "config.yaml")
    ctx = Context(spec, Registry(Path(registry), create=False), run, torch.device("cpu"), False)
    opts = parse_options(ctx)
    raw = load(ctx, min_units(ctx))
    arrays = whitened(raw, opts, shrink, prepare(ctx, raw, opts, seed))
    sd = prepare(ctx, arrays, opts, seed)  # the same roles and test rows: they do not depend on pressures
    shared = train_shared(sd.train, sd.train_stats, shared_shape(ctx, opts), "none", spec.training, seed,
                          "cpu")
    rows = adapted_rows(ctx, arrays, sd, opts, shared, seed, [Budget(0.0, "seconds", "spread")]).rows
    results = [r for r in json.loads((run / "metrics.json").read_text())["results"] if r["seed"] == seed]
    ref = {r["unit"]: r for r in results if r["method"] == "per_unit"}
    stats = {r["unit"]: r for r in results if r["method"] == "adapted:input_stats"}
    if set(stats) != set(sd.split.test):
        raise SystemExit(f"{run}: seed {seed}'s held-out units differ from the run's input_stats rows")

    def ratio(r: dict, key: str) -> float:
        return r[key] / ref[r["unit"]][key]

    return [{"unit": r["unit"], "seed": seed, **{f"{k}_{t}": ratio(row, f"{t}_rmse{u}")
                                                for k, row in (("whitened", r), ("stats", stats[r["unit"]]))
                                                for t, u in (("force", "_n"), ("angle", "_rad"))}}
            for r in rows]


def table(lines: list[dict]) -> str:
    """Markdown: mean ratio over unit-seeds with a 95% bootstrap interval, per method and target."""
    out = ["| label-free input | force ratio | angle ratio |", "|---|---|---|"]
    for key, name in (("stats", "per-barometer mean and spread (the run's `adapted:input_stats`)"),
                      ("whitened", "whitened (ZCA of the same seconds)")):
        cells = []
        for target in ("force", "angle"):
            m, lo, hi = mean_interval([line[f"{key}_{target}"] for line in lines])
            cells.append(f"{m:.2f}x [{lo:.2f}, {hi:.2f}]")
        out.append(f"| {name} | {' | '.join(cells)} |")
    units = len({line["unit"] for line in lines})
    return "\n".join(out) + f"\n\n{len(lines)} unit-seeds over {units} units.\n"


def main() -> None:
    ap = diagnostic_parser(__doc__)
    ap.add_argument("--shrink", type=float, default=0.0, help="weight of the identity in the correlation")
    a = ap.parse_args()

    def render(seeds: list[int], lines: list) -> str:
        return (f"# Label-free whitening: `{a.run.name}`, seeds {seeds}, shrink {a.shrink:g}\n\n"
                f"{table(lines)}")

    diagnose(a, lambda s: seed_lines(a.run, a.registry, s, a.shrink), render)


if __name__ == "__main__":
    main()
