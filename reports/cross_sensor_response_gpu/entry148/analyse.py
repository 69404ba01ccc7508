"""Research log entry 148: entry 147's designed arm with each unit's transfer-only network
(`transfer_check`). Prints rule 1 (every held-out row's plan-width fields against entry 147's), rule 2 (per
fold, the spread over its validation units of log(needed / own) for the transfer-only widths against the
plan's, and the decision written down) and, read after it and deciding nothing, the transfer-only widths'
ceiling on the held-out units and their intervals as recorded. Held-out rows record both widths times their
fold's factor (`fleet_halfwidth`, `transfer_halfwidth`), so the held-out figures compare those. From the
repository root:

    python reports/cross_sensor_response_gpu/entry148/analyse.py
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

from anytip.rundir import read_json

G = Path("reports/cross_sensor_response_gpu")
RUNS = [G / f"entry148/at120/fleet88_seed{k}" for k in (0, 1)]
BEFORE = [G / f"entry147/at120/fleet88_seed{k}" for k in (0, 1)]
METHODS = ("response@designed", "response+use@designed")
OUTPUTS = ("fx", "fy", "fz", "theta", "phi")
RULE = 0.85  # the transfer-only spread at most this times the plan's, in both folds
ANALYSE_106 = runpy.run_path(str(G / "entry106/analyse.py"))  # rows_by_unit, same, below
ceiling = runpy.run_path(str(G / "entry147/analyse.py"))["ceiling"]
rows_by_unit, same = ANALYSE_106["rows_by_unit"], ANALYSE_106["same"]


def rule_1() -> str:
    """The plan-width fields of every held-out row against entry 147's."""
    keys = [f"{o}_{k}" for o in OUTPUTS for k in ("halfwidth", "fleet_halfwidth", "margin_halfwidth",
                                                  "fleet_coverage", "margin_coverage")]
    return "rule 1:\n" + "\n".join(f"  {m}: {same(rows_by_unit(RUNS, m), rows_by_unit(BEFORE, m), keys)}"
                                   for m in METHODS)


def spreads(run: Path, seed: int) -> tuple[float, float]:
    """(plan, transfer-only): the spread over the fold's validation units of log(needed / own), mean over
    outputs; the plan's from the recorded learners, the transfer-only one as recorded."""
    iv = read_json(run / f"models/response_seed{seed}.json")
    iv = iv.get("meta", iv)["intervals"]
    val = read_json(run / "provenance.json")["cross_sensor"][f"seed{seed}"]["units"]["val"]
    learners = iv["units_by_strategy"]["designed"]["120"]
    ratio = np.log([[learners[u]["needed"][o] / learners[u]["own"][o] for o in OUTPUTS] for u in val])
    transfer = iv["log_ratio_spread_by_strategy"]["transfer"]["designed"]["120"]
    return float(ratio.std(axis=0, ddof=1).mean()), float(np.mean([transfer[o] for o in OUTPUTS]))


def rule_2() -> str:
    """Per fold, the two spreads on the same validation units, and the decision."""
    got = [spreads(run, seed) for seed, run in enumerate(RUNS)]
    lines = [f"  fold {k}: plan {p:.3f}, transfer-only {t:.3f} (x{t / p:.2f})"
             for k, (p, t) in enumerate(got)]
    taken = all(t <= RULE * p for p, t in got)
    lines.append(f"  decision: {'H-session taken' if taken else 'H-unit stands'} "
                 f"(the rule: transfer-only at most x{RULE} of the plan's in both folds)")
    return "rule 2, the validation units:\n" + "\n".join(lines)


def held_out() -> str:
    """The transfer-only widths on the held-out units: their ceiling and their intervals as recorded."""
    rows = rows_by_unit(RUNS, METHODS[0])

    def field(key: str) -> np.ndarray:
        return np.array([[r[f"{o}_{key}"] for o in OUTPUTS] for r in rows.values()])

    needed80 = field("needed80_halfwidth")
    lines = []
    for name, width in (("plan", "fleet_halfwidth"), ("transfer-only", "transfer_halfwidth")):
        lines.append(f"  {name} widths: one factor per output puts {ceiling(RUNS, METHODS[0], width)}")
    cover = field("transfer_coverage")
    lines.append(f"  transfer-only intervals as recorded (4 validation units' factor): "
                 f"{np.mean((cover >= 0.85) & (cover <= 0.95)):.1%} of {cover.size} in band, "
                 f"{int((cover < 0.80).sum())} below 0.80, lowest {cover.min():.3f}")
    log_ratio = np.log(needed80 / field("transfer_halfwidth")), np.log(needed80 / field("fleet_halfwidth"))
    lines.append("  spread over held-out units of log(needed80 / width), transfer-only / plan: " + ", ".join(
        f"{o} {a:.3f} / {b:.3f}" for o, a, b in zip(OUTPUTS, log_ratio[0].std(0, ddof=1),
                                                   log_ratio[1].std(0, ddof=1), strict=True)))
    return "also read (decides nothing), the held-out units, the plan alone:\n" + "\n".join(lines)


def main() -> None:
    print(rule_1())
    print(rule_2())
    print(held_out())


if __name__ == "__main__":
    main()
