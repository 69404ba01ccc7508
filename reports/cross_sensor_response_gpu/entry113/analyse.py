"""Research log entry 113: a unit's own half-width pooled toward the fleet's typical one.

Today's interval rule takes a new unit's half-width as its plan's own times the fleet factor: in logs,
log width = a_d + b log own with the slope b = 1. If the plan's own half-width is a noisy estimate of what the
unit's test rows need, a slope under 1 (empirical-Bayes pooling toward the learners' typical width) narrows
the spread of log(needed / width) over units, and with it the tail below the floor. This reads the learner
records that entries 106, 108, 110 and 111 saved (28 learners per fold: 4 validation and 24 factor units) and
prints, per record set, fold and kind (plan alone, with ordinary use):

1. the slope fitted on all the fold's learners (least squares, clipped to [0, 1]; one for all outputs, or
   one per output) and the spread it leaves, in-sample: the ceiling of pooling on these learners;
2. each learner left out in turn (a and b fitted on the others, as `fleet_margin.left_out_widths` does for
   b = 1): the spread and, at margin 1, the left-out unit-outputs below the floor and in the band;
3. the held-out units under each rule with the learners' margin (`fleet_margin.leave_one_out_margin`'s rule
   over the rule's own left-out widths), against the widths the runs recorded (the check: b = 1 rebuilt here
   must equal the recorded `<output>_margin_halfwidth`);
4. deciding nothing: the held-out units' excess, log(needed / width), split into a part common to a unit's
   five outputs and the rest, and its correlation with what a calibration knows before any test.

No run: every figure comes from the committed records. From the repository root:

    python reports/cross_sensor_response_gpu/entry113/analyse.py
"""

from __future__ import annotations

import runpy
from pathlib import Path
from typing import Any

import numpy as np

from anytip.rundir import read_json
from anytip.uncertainty.fleet_margin import Learner, margin_over

G = Path("reports/cross_sensor_response_gpu")
OUTPUTS = ("fx", "fy", "fz", "theta", "phi")
KINDS = {"": "response@cover_informative", "use_": "response+use@cover_informative"}
SETS = {"106": [G / f"entry106/fleet88_cpu_use/fleet88_seed{k}" for k in (0, 1)],
        "108": [G / f"entry108/fleet88r_use/fleet88_seed{k}" for k in (0, 1)],
        "110": [G / f"entry110/fleet88r_both/fleet88_seed{k}" for k in (0, 1)],
        "111": [G / f"entry111/fleet88x_seed{k}" for k in (0, 1)]}
FOLD_TABLE = runpy.run_path("scripts/fold_table.py")  # rows_of: a run's metrics.json rows


def learners(run: Path, seed: int, kind: str) -> list[Learner]:
    """The fold's learners at `cover_informative`, 120 s, as the run recorded them."""
    header = read_json(run / f"models/response_seed{seed}.json")
    records = header.get("meta", header)["intervals"][f"{kind}units_by_strategy"]["cover_informative"]["120"]
    return [Learner.from_record(records[u], OUTPUTS) for u in sorted(records)]


def held_out(run: Path, method: str) -> list[dict[str, Any]]:
    """The fold's held-out rows of `method` (`rows.json` where a fresh-unit driver wrote one)."""
    fresh = run / "rows.json"
    rows = read_json(fresh)["rows"] if fresh.exists() else FOLD_TABLE["rows_of"]([run])
    return [r for r in rows if r["method"] == method]


RULES = ("b=1", "shared", "per-output")  # today's; one pooled slope; a pooled slope per output


def fit(own: np.ndarray, needed: np.ndarray, rule: str) -> tuple[np.ndarray, np.ndarray]:
    """Per output intercepts a (D,) and slopes b (D,) of log needed on log own over units (U, D): b = 1
    (today's fleet factor, a = its log), one least-squares slope for all outputs, or one per output;
    fitted slopes are clipped to [0, 1] (0: the fleet's typical width, 1: the plan's own)."""
    x, y = np.log(own), np.log(needed)
    xc, yc = x - x.mean(0), y - y.mean(0)
    b = {"b=1": np.ones(x.shape[1]),
         "shared": np.full(x.shape[1], (xc * yc).sum() / (xc * xc).sum()),
         "per-output": (xc * yc).sum(0) / (xc * xc).sum(0)}[rule]
    b = np.clip(b, 0.0, 1.0)
    return y.mean(0) - b * x.mean(0), b


def widths(own: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Half-widths (U, D) from own half-widths (U, D) under the rule (a, b)."""
    return np.exp(a) * own ** b


def stack(fold: list[Learner], field: str) -> np.ndarray:
    """One field of every learner, (U, D)."""
    return np.stack([getattr(u, field) for u in fold])


def left_out(fold: list[Learner], rule: str) -> np.ndarray:
    """Each learner's half-widths (U, D) from the rule fitted on the others."""
    own, needed = stack(fold, "own"), stack(fold, "needed")
    return np.stack([widths(own[k], *fit(np.delete(own, k, 0), np.delete(needed, k, 0), rule))
                     for k in range(len(fold))])


def margin(fold: list[Learner], base: np.ndarray) -> tuple[float, int, float]:
    """The learners' margin on left-out widths `base` (today's rule, `fleet_margin.margin_over`), and at
    margin 1 the left-out unit-outputs below the floor and the share in the band."""
    got = margin_over(base, *(stack(fold, f) for f in ("at_floor", "at_low", "at_high")))
    return got.margin, got.below[1.0], got.in_band[1.0]


def spread(fold: list[Learner], base: np.ndarray) -> float:
    """The standard deviation of log(needed / width) over the learners' unit-outputs."""
    return float(np.log(stack(fold, "needed") / base).std())


def row_array(rows: list[dict[str, Any]], key: str) -> np.ndarray:
    """(units, outputs) of `<output>_<key>` from held-out rows."""
    return np.array([[r[f"{o}_{key}"] for o in OUTPUTS] for r in rows])


def target(w: np.ndarray, rows: list[dict[str, Any]]) -> tuple[int, float]:
    """Held-out unit-outputs below the floor and the share in the band at half-widths w (units, outputs)."""
    floor, low, high = (row_array(rows, f"needed{p}_halfwidth") for p in (80, 85, 95))
    return int((w < floor).sum()), float(((w >= low) & (w <= high)).mean())


def fold_line(name: str, seed: int, kind: str, tally: dict[str, list]) -> str:
    """Rules 1 and 2 for one fold and kind; adds its held-out widths under each rule to `tally`."""
    run = SETS[name][seed]
    fold = learners(run, seed, kind)
    own, needed = stack(fold, "own"), stack(fold, "needed")
    cells, rows = [], held_out(run, KINDS[kind])
    for rule in RULES:
        a, b = fit(own, needed, rule)
        base = left_out(fold, rule)
        m, below, band = margin(fold, base)
        w = widths(row_array(rows, "halfwidth"), a, b) * m
        if rule == "b=1":
            recorded = row_array(rows, "margin_halfwidth")
            assert np.allclose(w, recorded, rtol=1e-9), f"{run}: today's rule does not rebuild the record"
        tally.setdefault((name, kind, rule), []).append((w, rows))
        in_sample = float(np.log(needed / widths(own, a, b)).std())
        slopes = "/".join(f"{v:.2f}" for v in b) if rule == "per-output" else f"{b[0]:.2f}"
        cells.append(f"{rule}: b {slopes}, sd {in_sample:.3f} in-sample, {spread(fold, base):.3f} left out, "
                     f"below {below}, band {band:.0%}, margin {m:g}")
    return f"  {name} fold {seed} {kind or 'plan'}:\n    " + "\n    ".join(cells)


def excess_parts(rows: list[dict[str, Any]], w: np.ndarray) -> str:
    """Rule 4: the held-out excess log(needed90 / w), needed90 as the band edges' geometric mean, split
    into each unit's mean over outputs (after each output's mean) and the rest; and its correlation with
    the plan's own width over the fleet's typical one and with the plan's effective rows."""
    e = np.log(np.sqrt(row_array(rows, "needed85_halfwidth") * row_array(rows, "needed95_halfwidth")) / w)
    e = e - e.mean(0)
    unit = e.mean(1, keepdims=True)
    rel = np.log(row_array(rows, "halfwidth") / row_array(rows, "typical_halfwidth"))
    n_eff = np.log([r["n_effective"] for r in rows])
    corr = [np.corrcoef(rel[:, d], e[:, d])[0, 1] for d in range(len(OUTPUTS))]
    return (f"variance {e.var():.4f}: unit-common {np.broadcast_to(unit, e.shape).var():.4f} "
            f"({np.broadcast_to(unit, e.shape).var() / e.var():.0%}); corr with own/typical "
            f"{', '.join(f'{o} {c:+.2f}' for o, c in zip(OUTPUTS, corr, strict=True))}; "
            f"corr of the unit part with log n_effective {np.corrcoef(n_eff, unit[:, 0])[0, 1]:+.2f}")


def main() -> None:
    tally: dict[str, list] = {}
    print("rules 1-2, the learners (28 per fold), b = 1 (today) against a pooled slope:")
    for name in SETS:
        for seed in (0, 1):
            for kind in KINDS:
                print(fold_line(name, seed, kind, tally))
    print("\nrule 3, held-out unit-outputs: below 0.80, share in [0.85, 0.95]:")
    for (name, kind, rule), parts in tally.items():
        w = np.concatenate([p[0] for p in parts])
        rows = [r for p in parts for r in p[1]]
        below, band = target(w, rows)
        print(f"  {name} {kind or 'plan'} {rule}: {len(rows)} units, below {below}, in band {band:.1%}")
        if rule == "b=1":
            print(f"    rule 4: {excess_parts(rows, w)}")


if __name__ == "__main__":
    main()
