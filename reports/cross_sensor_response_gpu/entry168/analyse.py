"""Research log entry 168's reading. (a) Entry 44's zero-shot rows (the search started from the encoder's
codes, 600 s of ordinary use) against the runs' own references (rule 1: entry 44's figures back) and against
entry 165's references kept over three starts (rule 2). (b) `time_calibrate.sh`'s log: today's code over entry
134's commit, paired per unit, round and arm (rule 3), and every calibration's fit against 10 s (rule 4).
Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry168/analyse.py
"""

import re
import runpy
from pathlib import Path

import numpy as np

from anytip.rundir import read_json

HERE = Path(__file__).parent
GPU = HERE.parent
E165 = runpy.run_path(str(GPU / "entry165" / "analyse.py"))
t_interval = runpy.run_path(str(GPU / "entry162" / "analyse.py"))["t_interval"]
ZERO_SHOT = GPU.parent / "cross_sensor_label_free_codes" / "scale" / "encoder_start" / "held_out"
ARM, METHOD = "joint_scale_encoder", "zero_shot"
TIMING = HERE / "logs" / "time_calibrate.log"


def zero_shot_rows(registry: str) -> list[dict]:
    """Entry 44's held-out rows of the registry's folds, as rows of method `zero_shot` (budget 0)."""
    rows = []
    for k in E165["FOLDS"][registry]:
        got = read_json(ZERO_SHOT / f"{registry}_seed{k}.json")
        rows += [{**r, "method": METHOD, "budget_s": 0.0} for r in got["rows"]
                 if r["arm"] == ARM and r["role"] == "test"]
    return rows


def zero_shot() -> None:
    """Rules 1-2: the zero-shot figure against the runs' references and against three starts."""
    for registry in E165["FOLDS"]:
        shot = zero_shot_rows(registry)
        rows = shot + list(E165["old_references"](registry).values())
        one, _ = E165["cell"](rows, METHOD, 0.0)
        new, _ = E165["new_references"](registry)
        three, got = E165["cell"](E165["swapped"](rows, new), METHOD, 0.0)
        verdict = "met" if max(m for m, _, _ in got) <= 2.0 else "missed"  # the goal is on the mean alone
        print(f"{registry} zero-shot ({len(shot)} units): against the run's references {one}; against three "
              f"starts {three}: {verdict} (goal 2.0x on the mean)")


def timing() -> None:
    """Rules 3-4: lines 'ARM CODE UNIT round R wall_s S command_s C' of the timing log."""
    got: dict[tuple[str, str, str, str], float] = {}
    for line in TIMING.read_text().splitlines():
        m = re.match(r"(\S+) (\S+) (\S+) round (\d+) wall_s ([\d.]+)", line)
        if m:
            got[m.group(1, 2, 3, 4)] = float(m.group(5))
    for arm in sorted({k[0] for k in got}):
        for code in ("today", "entry134"):
            w = [s for k, s in got.items() if k[0] == arm and k[1] == code]
            print(f"{arm}, {code}'s code: fit and fold {min(w):.2f}-{max(w):.2f} s (mean {np.mean(w):.2f}, "
                  f"{len(w)} calibrations), {sum(s < 10 for s in w)} under 10 s")
    logs = np.array([np.log(s / got[(a, "entry134", u, r)])
                     for (a, c, u, r), s in got.items() if c == "today"])
    m, lo, hi = np.exp(t_interval(logs))
    print(f"today's code over entry 134's, paired ({len(logs)} pairs): x{m:.3f} [{lo:.3f}, {hi:.3f}]")


if __name__ == "__main__":
    zero_shot()
    if TIMING.exists():
        timing()
