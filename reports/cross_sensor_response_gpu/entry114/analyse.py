"""Research log entry 114 (b): the learners' own half-widths in-sample (today's) against out of fold.

Reads `entry114/oof_seed{0,1}/learners.json` (written by `oof_learners.py`) and prints the rules written down
in `docs/research_log.md`, entry 114:
1. the gate: every learner's in-sample half-widths equal the run's recorded `own` (relative difference under
   1e-5 in every output);
2. per fold and over both, the spread (standard deviation over the learners' unit-outputs) of log(needed /
   width), width = own times the factor of the other learners (`fleet_margin.left_out_widths`), in-sample and
   out of fold, and the verdict (out of fold is worth building if its spread is at most 0.85 times the
   in-sample one in both folds);
3. also read: the left-out unit-outputs below 0.80 and the share in [0.85, 0.95] at margin 1 under each, the
   correlation over unit-outputs of log(needed / own) between the two, and the calibrations per unit.
From the repository root:

    python reports/cross_sensor_response_gpu/entry114/analyse.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from anytip.rundir import read_json
from anytip.uncertainty.fleet_margin import Learner, left_out_widths

HERE = Path("reports/cross_sensor_response_gpu/entry114")
OUTPUTS = ("fx", "fy", "fz", "theta", "phi")
TOLERANCE = 1e-5
RATIO = 0.85  # rule 2: out of fold is worth building at or below this share of the in-sample spread


def vec(by_output: dict[str, float]) -> np.ndarray:
    return np.array([by_output[o] for o in OUTPUTS])


def learners(units: dict[str, dict], own: str) -> list[Learner]:
    """The fold's learners with the recorded test half-widths and `own` ("in_sample" or "oof")."""
    return [Learner(vec(u[own]), *(vec(u["recorded"][f]) for f in Learner._fields[1:]))
            for u in units.values()]


def gate(units: dict[str, dict]) -> float:
    """Rule 1: the largest relative difference of the in-sample half-widths from the recorded `own`."""
    return max(float(np.max(np.abs(vec(u["in_sample"]) / vec(u["recorded"]["own"]) - 1)))
               for u in units.values())


def read(fold: list[Learner]) -> tuple[np.ndarray, int, float]:
    """log(needed / width) over the fold's unit-outputs (U, D), and at margin 1 the left-out unit-outputs
    below the floor and the share in the band."""
    base, floor, low, high = left_out_widths(fold)
    needed = np.stack([u.needed for u in fold])
    return np.log(needed / base), int((base < floor).sum()), float(((base >= low) & (base <= high)).mean())


def main() -> None:
    folds = [read_json(HERE / f"oof_seed{k}/learners.json") for k in (0, 1)]
    worst = max(gate(f["units"]) for f in folds)
    print(f"rule 1, the gate: largest relative difference of in-sample from recorded own {worst:.1e} "
          f"({'holds' if worst < TOLERANCE else 'fails: nothing below is read'})")
    if worst >= TOLERANCE:
        return
    ratios, logs = [], {"in_sample": [], "oof": []}
    print("\nrule 2, spread of log(needed / own x factor of the others), and rule 3 at margin 1:")
    for k, f in enumerate(folds):
        cells = {}
        for own in logs:
            excess, below, band = read(learners(f["units"], own))
            logs[own].append(excess)
            cells[own] = float(excess.std())
            print(f"  fold {k} {own:9s}: spread {excess.std():.3f} (per output "
                  f"{' '.join(f'{v:.3f}' for v in excess.std(0))}); below 0.80 {below}, in band {band:.0%}")
        ratios.append(cells["oof"] / cells["in_sample"])
        print(f"  fold {k}: out of fold / in-sample {ratios[-1]:.3f}")
    both = {own: np.concatenate(v) for own, v in logs.items()}
    print(f"  both folds: in-sample {both['in_sample'].std():.3f}, out of fold {both['oof'].std():.3f} "
          f"({both['oof'].std() / both['in_sample'].std():.3f})")
    verdict = "worth building (both folds" if all(r <= RATIO for r in ratios) else "not the lever (not both"
    print(f"  verdict: {verdict} at or below {RATIO})")
    own_logs = [np.log(np.stack([vec(u["recorded"]["needed"]) / vec(u[own]) for u in f["units"].values()]))
                for f in folds for own in ("in_sample", "oof")]
    r = np.corrcoef(np.concatenate([own_logs[0], own_logs[2]]).ravel(),
                    np.concatenate([own_logs[1], own_logs[3]]).ravel())[0, 1]
    print(f"\nrule 3: correlation of log(needed / own) in-sample and out of fold over the unit-outputs "
          f"{r:+.2f}; "
          f"calibrations per unit: 1 + {folds[0]['folds']} (fold wall {folds[0]['wall_s']:.0f} s, "
          f"{folds[1]['wall_s']:.0f} s for 28 learners each)")


if __name__ == "__main__":
    main()
