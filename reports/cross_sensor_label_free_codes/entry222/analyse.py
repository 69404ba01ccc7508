"""Research log entry 222: the fingertip's zero-shot fit (entry 44's arm on other16's four folds) over four
draws of its search contacts.

    python reports/cross_sensor_label_free_codes/entry222/analyse.py

Reads `entry222/drawD/other16_seedK.json` (D = 0-3, K = 0-3), the rows of `scripts/label_free_codes.py
--search-draw D`. Rule 1: draw 0 against entry 44's committed rows. Rule 2: per held-out unit, force RMSE over
the draws, max over min. Rule 3: each draw's figure against entry 165's three-start references, as entry 168
read entry 44's. Rule 4: the lowest final objective's pick, and the validation units' spread.
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

from anytip.rundir import read_json

HERE = Path(__file__).resolve().parent
GPU = HERE.parent.parent / "cross_sensor_response_gpu"
E165 = runpy.run_path(str(GPU / "entry165" / "analyse.py"))
ENTRY44 = HERE.parent / "scale" / "encoder_start" / "held_out"
ARM, METHOD, REGISTRY = "joint_scale_encoder", "zero_shot", "other16"
FOLDS, DRAWS = (0, 1, 2, 3), (0, 1, 2, 3)
KEYS = ("force_rmse_n", "angle_rmse_rad")


def arm_rows(path: Path) -> list[dict]:
    """The zero-shot arm's rows of one run file (validation and held-out units)."""
    return [r for r in read_json(path)["rows"] if r["arm"] == ARM]


def draws() -> dict[int, list[dict]]:
    """{draw: every fold's rows} for the draws whose four folds have finished."""
    got = {d: [HERE / f"draw{d}" / f"{REGISTRY}_seed{k}.json" for k in FOLDS] for d in DRAWS}
    done = {d: paths for d, paths in got.items() if all(p.exists() for p in paths)}
    return {d: [r for p in paths for r in arm_rows(p)] for d, paths in done.items()}


def gate(today: list[dict]) -> None:
    """Rule 1: draw 0 against entry 44's rows, each unit's force and angle RMSE."""
    old = {r["unit"]: r for k in FOLDS for r in arm_rows(ENTRY44 / f"{REGISTRY}_seed{k}.json")}
    worst = max(abs(r[key] / old[r["unit"]][key] - 1) for r in today for key in KEYS)
    verdict = "holds" if worst <= 1e-6 else "differs: draw 0 of this entry is the control"
    print(f"rule 1: draw 0 over entry 44's rows, largest relative difference {worst:.2e} over {len(today)} "
          f"units ({verdict})")


def by_unit(got: dict[int, list[dict]], role: str, key: str) -> dict[str, list[float]]:
    """{unit: [key per draw]} of the units of one role."""
    out: dict[str, list[float]] = {}
    for d in sorted(got):
        for r in got[d]:
            if r["role"] == role:
                out.setdefault(r["unit"], []).append(r[key])
    return out


def spread(got: dict[int, list[dict]], role: str) -> None:
    """Rule 2 (held out) and rule 4's second half (validation): max over min per unit."""
    for key in KEYS:
        per = {u: max(v) / min(v) for u, v in by_unit(got, role, key).items()}
        worst = max(per, key=per.get)
        median = np.median(list(per.values()))
        print(f"  {role}, {key}: max over min per unit over {len(got)} draws, median x{median:.3f} "
              f"(largest x{per[worst]:.3f}, {worst}; {len(per)} units)")


def against_references(got: dict[int, list[dict]]) -> None:
    """Rule 3: each draw's held-out rows against the run's and the three-start references (entry 168)."""
    old = list(E165["old_references"](REGISTRY).values())
    new, _ = E165["new_references"](REGISTRY)
    means = []
    for d, rs in sorted(got.items()):
        shot = [{**r, "method": METHOD, "budget_s": 0.0} for r in rs if r["role"] == "test"]
        one, _ = E165["cell"](shot + old, METHOD, 0.0)
        three, cells = E165["cell"](E165["swapped"](shot + old, new), METHOD, 0.0)
        means.append(cells[0][0])
        print(f"  draw {d} ({len(shot)} held-out units): against the runs' references {one}; against three "
              f"starts {three}")
    met = sum(m <= 2.0 for m in means)
    print(f"  force against three starts over the draws: {min(means):.3f}x-{max(means):.3f}x; the 2.0x goal "
          f"met in {met} of {len(means)} draws")


def objective_pick(got: dict[int, list[dict]]) -> None:
    """Rule 4: how often the draw of lowest final objective is the unit's draw of lowest force RMSE."""
    hits = n = 0
    for role in ("val", "test"):
        force = by_unit(got, role, "force_rmse_n")
        final = by_unit(got, role, f"objective_{ARM}")
        for u, f in force.items():
            ends = [o[-1] for o in final[u]]
            hits += int(np.argmin(ends) == np.argmin(f))
            n += 1
    print(f"  the lowest final objective picks the unit's best draw in force on {hits} of {n} units "
          f"(chance {n / len(got):.0f})")


def main() -> None:
    got = draws()
    if 0 in got:
        gate([r for r in got[0]])
    print(f"draws with all four folds: {sorted(got)}")
    if len(got) < 2:
        return
    print("rule 2:")
    spread(got, "test")
    print("rule 3:")
    against_references(got)
    print("rule 4:")
    objective_pick(got)
    spread(got, "val")


if __name__ == "__main__":
    main()
