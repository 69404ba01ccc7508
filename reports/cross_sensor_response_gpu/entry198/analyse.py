"""Research log entry 198's reading: the 90% intervals of `anytip calibrate --plan-strategy designed
--use-log` (120 s, a log weighed as the contact seconds it holds) under three fleet factors, each applied
to the half-widths the calibration recorded (`intervals.own_halfwidth`) and scored on the unit's full
runs, which no calibration reads. U: the factor the benchmark learnt for codes fitted with its 600 s of
ordinary use (today's); A: the one it learnt for the plan alone; I: between them, geometric in the share s
of the benchmark's use seconds the log held, A^(1 - s) U^s. Nothing is trained or calibrated again. A was
taken: since this entry `anytip calibrate` itself gives a unit with a log lighter than the benchmark's use
A's factor.

Validation units (the decision): entry 191's arm H, 64 fresh units of two elastomers. Held-out units (read
after the decision): entry 182's L120 (16 fleet88 units, scored on data/fleet88p as entry 182 scored them)
and entry 186's D1 (other16's 16 units, each under the fold that holds it out, scored on data/other16 as
entry 186 scored them).

    python reports/cross_sensor_response_gpu/entry198/analyse.py > \\
        reports/cross_sensor_response_gpu/entry198/logs/analyse.log
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import NamedTuple

import numpy as np
import torch

from anytip.calibrate.records import at_budget, strategy_table
from anytip.data.arrays import load_arrays
from anytip.data.registry import Registry
from anytip.models.io import RESPONSE_FORMAT, load_models, model_paths, read_header
from anytip.train.metrics import predict
from anytip.uncertainty.conformal import coverage, interval

BAND, FLOOR, BUDGET, STRATEGY = (0.85, 0.95), 0.80, 120.0, "designed"
ARMS = ("U", "I", "A")
# (name, calibrations' glob, registry, role)
SETS = (("default fingertip, 32 fresh (SIM41, entry 191 H)", "build/entry191/H-f*/SIM41-*", "data/val191d",
         "validation"),
        ("other elastomer, 32 fresh (SIM24, entry 191 H)", "build/entry191/H-o*/SIM24-*", "data/val191o",
         "validation"),
        ("fleet88, 16 held out (SIM40, entry 182 L120)", "build/entry182/L120/SIM40-*", "data/fleet88p",
         "held-out"),
        ("other16, 16 held out (SIM23, entry 186 D1)", "build/entry186/D1/SIM23-*", "data/other16",
         "held-out"))


def factors(response_model: str, seconds: float) -> tuple[dict[str, np.ndarray], float]:
    """The three arms' factors (D,) for a calibration under `response_model` whose log held `seconds` of
    contact, and s, the share of the benchmark's use seconds it held (at most 1)."""
    meta = read_header(model_paths(Path(response_model))[1], RESPONSE_FORMAT)["meta"]
    rec, names = meta["intervals"], meta["output_names"]
    use = at_budget(strategy_table(rec, "use_fleet_factor", STRATEGY), BUDGET)
    alone = at_budget(strategy_table(rec, "fleet_factor", STRATEGY), BUDGET)
    for key in ("margin", "use_margin"):  # every arm here is the factor alone: no margin recorded above 1
        assert at_budget(strategy_table(rec, key, STRATEGY), BUDGET)["margin"] == 1.0, (response_model, key)
    u, a = (np.array([t[n] for n in names]) for t in (use, alone))
    s = min(seconds / float(meta["label_free"]["recipe"]["seconds"]), 1.0)
    return {"U": u, "A": a, "I": a ** (1 - s) * u ** s}, s


class FullRuns(NamedTuple):
    """A calibration read on its unit's full runs, which no calibration reads: its record, its network's
    metadata and output names, its recorded own half-widths (D,), and its predictions and the targets there
    (n, D)."""

    rec: dict
    meta: dict
    names: tuple[str, ...]
    own: np.ndarray
    pred: np.ndarray
    target: np.ndarray


def on_full_runs(calibration: Path, registry: Registry) -> FullRuns:
    """`FullRuns` of the calibration directory (entries 198-202 read theirs with it)."""
    rec = json.loads((calibration / "calibration.json").read_text())
    meta = read_header(model_paths(calibration / "model.safetensors")[1])["meta"]
    names = tuple(meta["output_names"])
    runs = [r for r in registry.list_runs(unit=rec["unit"]) if r.protocol == "full"]
    arrays = load_arrays(registry, runs)
    net = load_models(calibration / "model.safetensors")
    X = torch.from_numpy(arrays.pressure)[None]
    pred = predict(net.model, net.in_scaler, net.out_scaler, X)[0].numpy()
    own = np.array([rec["intervals"]["own_halfwidth"][n] for n in names])
    return FullRuns(rec, meta, names, own, pred, arrays.targets)


def coverages(calibration: Path, registry: Registry) -> tuple[dict[str, np.ndarray], float, bool]:
    """Per arm, the coverage (D,) of the calibration's network on its unit's full runs; s; and the gate: the
    recorded factor is U and, where the calibration's other runs are exactly the full runs, its recorded
    coverage is U's."""
    rec, meta, names, own, pred, target = on_full_runs(calibration, registry)
    got, s = factors(meta["response_model"], rec["unlabeled_seconds"])
    out = {arm: coverage(*interval(pred, own * f), target) for arm, f in got.items()}
    recorded = np.array([rec["intervals"]["fleet_factor"][n] for n in names])
    same = bool(np.allclose(recorded, got["U"], rtol=1e-12))
    if rec["check"]["rows"] == len(pred):
        cov = np.array([rec["intervals"]["coverage_on_other_runs"][n] for n in names])
        same &= bool(np.allclose(cov, out["U"], atol=1e-6))
    return out, s, same


def summary(cov: np.ndarray) -> str:
    """In band, below the floor, above the band and the mean per output of unit-outputs (n, D)."""
    flat = cov.ravel()
    in_band = np.mean((flat >= BAND[0]) & (flat <= BAND[1]))
    means = " ".join(f"{m:.3f}" for m in cov.mean(0))
    return (f"{100 * in_band:.1f}% in band, {int(np.sum(flat < FLOOR))} below {FLOOR}, "
            f"{int(np.sum(flat > BAND[1]))} above {BAND[1]}, lowest {flat.min():.3f}; "
            f"mean per output {means}")


def main() -> None:
    totals: dict[str, dict[str, list[np.ndarray]]] = {}
    for name, pattern, root, role in SETS:
        registry = Registry(root)
        found = sorted(p for p in Path().glob(pattern) if p.is_dir())
        per_arm: dict[str, list[np.ndarray]] = {a: [] for a in ARMS}
        shares, gate = [], 0
        for calibration in found:
            cov, s, same = coverages(calibration, registry)
            shares.append(s)
            gate += same
            for a in ARMS:
                per_arm[a].append(cov[a])
        print(f"## {name} [{role}]: {len(found)} units, gate {gate} of {len(found)}, "
              f"s {min(shares):.3f}-{max(shares):.3f}")
        for a in ARMS:
            print(f"  {a}: {summary(np.array(per_arm[a]))}")
        for a in ARMS:
            totals.setdefault(role, {}).setdefault(a, []).extend(per_arm[a])
    for role, per_arm in totals.items():
        print(f"## all {role} units")
        for a in ARMS:
            print(f"  {a}: {summary(np.array(per_arm[a]))}")
    assert all(math.isfinite(float(np.sum(v))) for t in totals.values() for v in t.values())


if __name__ == "__main__":
    main()
