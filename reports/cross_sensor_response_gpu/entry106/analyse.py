"""Research log entry 106: the 90% intervals of the recipe with ordinary use and the plan's residual
correction (fleet88's CPU rescoring, `cover_informative`, 120 s, 24 factor units). Prints rule 1 (the
held-out errors against entry 105's on arm, the plan-alone interval fields against entry 104's), each
fold's factors and margins, the interval tables (`scripts/fold_table.py`: the factor alone and times its
leave-one-out margin) with the unit-outputs below 0.80 by name, and rule 3's diagnostic, a margin per
output, on this entry's runs and on entry 104's (whose held-out results were known before it was written
down). From the repository root:

    python reports/cross_sensor_response_gpu/entry106/analyse.py
"""

from __future__ import annotations

import runpy
from pathlib import Path
from typing import Any

import numpy as np

from anytip.pipelines.cross_sensor_jobs import band_edges, needed_key
from anytip.rundir import read_json
from anytip.uncertainty.conformal import fleet_factor
from anytip.uncertainty.fleet_margin import IN_BAND_SHARE, MARGIN_GRID, Learner, left_out_widths, meeting

G = Path("reports/cross_sensor_response_gpu")
RUNS = [G / f"entry106/fleet88_cpu_use/fleet88_seed{k}" for k in (0, 1)]
USE_CONTROL = [G / f"entry105/fleet88_cpu_use_on/fleet88_seed{k}" for k in (0, 1)]
PLAN_CONTROL = [G / f"entry104/fleet88_cpu_on/fleet88_seed{k}" for k in (0, 1)]
METHODS = ("response@cover_informative", "response+use@cover_informative")
OUTPUTS = ("fx", "fy", "fz", "theta", "phi")
FLOOR, LOW, HIGH = band_edges(0.9)
FOLD_TABLE = runpy.run_path("scripts/fold_table.py")  # its functions, not its command line
LEARNER_KEYS = FOLD_TABLE["LEARNER_KEYS"]


def rows_by_unit(runs: list[Path], method: str) -> dict[str, dict[str, Any]]:
    """The runs' `method` rows by unit."""
    return {r["unit"]: r for r in FOLD_TABLE["rows_of"](runs) if r["method"] == method}


def factors(run: Path, seed: int) -> str:
    """A fold's fleet factors and leave-one-out margins, plan alone and with ordinary use, as recorded."""
    header = read_json(run / f"models/response_seed{seed}.json")
    iv = header.get("meta", header)["intervals"]

    def line(prefix: str, label: str) -> str:
        factor, margin = (iv[f"{prefix}{k}_by_strategy"]["cover_informative"]["120"]
                          for k in ("fleet_factor", "margin"))
        band = ", ".join(f"{m} {v:.0%}" for m, v in margin["in_band"].items())
        cells = ", ".join(f"{o} {factor[o]:.2f}" for o in OUTPUTS)
        return (f"  fold {seed} {label}: factor {cells}; margin {margin['margin']:g} "
                f"(below 0.80 by margin: {margin['below_floor']}; in band: {band})")

    return "\n".join(line(prefix, label) for prefix, label in (("", "plan alone"), ("use_", "with use")))


def same(mine: dict[str, dict[str, Any]], theirs: dict[str, dict[str, Any]], keys: list[str]) -> str:
    """How many units give equal `keys` in both, and the largest relative difference."""
    if set(mine) != set(theirs):
        return f"the units differ ({len(mine)} against {len(theirs)})"
    a = np.array([[mine[u][k] for k in keys] for u in sorted(mine)])
    b = np.array([[theirs[u][k] for k in keys] for u in sorted(mine)])
    return (f"{int(np.all(a == b, axis=1).sum())} of {len(a)} units equal; largest relative difference "
            f"{np.max(np.abs(a / b - 1)):.2e}")


def rule_1() -> str:
    """Held-out errors against entry 105's on arm; plan-alone interval fields against entry 104's on arm."""
    errors = ["force_rmse_n", "angle_rmse_rad"]
    lines = [f"  {m} errors: {same(rows_by_unit(RUNS, m), rows_by_unit(USE_CONTROL, m), errors)}"
             for m in METHODS]
    fields = [f"{o}_{k}" for o in OUTPUTS for k in ("halfwidth", "fleet_halfwidth", "margin_halfwidth")]
    lines.append(f"  {METHODS[0]} interval fields against entry 104: "
                 f"{same(rows_by_unit(RUNS, METHODS[0]), rows_by_unit(PLAN_CONTROL, METHODS[0]), fields)}")
    return "rule 1:\n" + "\n".join(lines)


def below(rows: dict[str, dict[str, Any]], kind: str) -> list[str]:
    """The unit-outputs whose `kind` interval covers less than the floor of their test rows."""
    return [f"{u} {o} {r[f'{o}_{kind}_coverage']:.3f}" for u, r in sorted(rows.items()) for o in OUTPUTS
            if r[f"{o}_{kind}_coverage"] < FLOOR]


def output_margins(learners: list[Learner]) -> np.ndarray:
    """Per output (D,): the smallest grid value under which none of the output's left-out learners falls
    below the floor and at least `IN_BAND_SHARE` of them lie in the band; 1 where none does."""
    base, floor, low, high = left_out_widths(learners)
    out = []
    for d in range(base.shape[1]):
        width = {m: base[:, d] * m for m in MARGIN_GRID}
        below = {m: int((w < floor[:, d]).sum()) for m, w in width.items()}
        in_band = {m: float(((w >= low[:, d]) & (w <= high[:, d])).mean()) for m, w in width.items()}
        ok = meeting(below, in_band, IN_BAND_SHARE)  # the learners' rule, one output at a time
        out.append(min(ok) if ok else 1.0)
    return np.array(out)


def per_output(runs: list[Path], method: str) -> str:
    """Rule 3's diagnostic: each fold's held-out widths (own times the recorded factor) times a margin per
    output learnt by the fold's learners; share of unit-outputs in the band, and those below the floor."""
    key = (LEARNER_KEYS[method.split("@")[0]], "cover_informative", "120")
    learners = FOLD_TABLE["fold_learners"](runs)
    in_band, low_ones, lines = [], [], []
    for seed, run in enumerate(runs):
        margins = output_margins(list(learners[str(run), seed][key].values()))
        cells = ", ".join(f"{o} {m:g}" for o, m in zip(OUTPUTS, margins, strict=True))
        lines.append(f"  fold {seed}: {cells}")
        for u, r in sorted(rows_by_unit([run], method).items()):
            for o, m in zip(OUTPUTS, margins, strict=True):
                w = r[f"{o}_fleet_halfwidth"] * m
                in_band.append(r[needed_key(o, LOW)] <= w <= r[needed_key(o, HIGH)])
                if w < r[needed_key(o, FLOOR)]:
                    low_ones.append(f"{u} {o}")
    return (f"{method}: margin per output, {np.mean(in_band):.0%} of {len(in_band)} in band, "
            f"{len(low_ones)} below {FLOOR:.2f} ({', '.join(low_ones) or 'none'})\n" + "\n".join(lines))


def resampled(runs: list[Path], method: str, draws: int = 2000, seed: int = 0) -> str:
    """Also read (decides nothing): how near the target lies to the factor's own noise. Each fold's factor
    (no margin) learnt again by a bootstrap draw of its learners, both folds drawn apart, applied to the
    held-out rows' plan half-widths: the share of draws that meet the target (at least 90% of unit-outputs
    in the band, none below the floor) and the median count below the floor."""
    key = (LEARNER_KEYS[method.split("@")[0]], "cover_informative", "120")
    learners, rng = FOLD_TABLE["fold_learners"](runs), np.random.default_rng(seed)
    below_n, in_band = np.zeros(draws, int), np.zeros(draws)
    for fold, run in enumerate(runs):
        mine = list(learners[str(run), fold][key].values())
        own, needed = np.stack([u.own for u in mine]), np.stack([u.needed for u in mine])
        held = list(rows_by_unit([run], method).values())
        width = np.array([[r[f"{o}_halfwidth"] for o in OUTPUTS] for r in held])
        floor, low, high = (np.array([[r[needed_key(o, e)] for o in OUTPUTS] for r in held])
                            for e in (FLOOR, LOW, HIGH))
        for b in range(draws):
            idx = rng.integers(0, len(mine), len(mine))
            w = width * fleet_factor(own[idx], needed[idx])
            below_n[b] += int((w < floor).sum())
            in_band[b] += float(((w >= low) & (w <= high)).sum())
    share = in_band / sum(len(rows_by_unit([run], method)) * len(OUTPUTS) for run in runs)
    met = np.mean((below_n == 0) & (share >= IN_BAND_SHARE))
    return (f"{method}: {draws} bootstrap draws of each fold's learners, the factor alone: target met in "
            f"{met:.0%}; below {FLOOR:.2f}: median {np.median(below_n):g}, 0 in {np.mean(below_n == 0):.0%}; "
            f"in band: median {np.median(share):.0%}")


def main() -> None:
    print(rule_1())
    print("\nfactors and margins:")
    for seed, run in enumerate(RUNS):
        print(factors(run, seed))
    rows = FOLD_TABLE["rows_of"](RUNS)
    for kind in ("fleet", "margin"):
        print(f"\n{kind} intervals:\n{FOLD_TABLE['table'](rows, kind)}")
        for m in METHODS:
            print(f"{m} below {FLOOR:.2f}: {', '.join(below(rows_by_unit(RUNS, m), kind)) or 'none'}")
    print(f"\nwhat one factor per output could do (chosen on the held-out units, a diagnostic):\n"
          f"{FOLD_TABLE['ceilings'](rows)}")
    print("\nrule 3, a margin per output (decides nothing):")
    for m in METHODS:
        print(per_output(RUNS, m))
    print("entry 104's runs (held-out results known before this was written down):")
    print(per_output(PLAN_CONTROL, METHODS[0]))
    print("\nalso read, the factor's noise (decides nothing):")
    for m in METHODS:
        print(resampled(RUNS, m))


if __name__ == "__main__":
    main()
