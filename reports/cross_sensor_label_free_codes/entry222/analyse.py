"""Research log entry 222: the fingertip's zero-shot fit (entry 44's arm on other16's four folds and fleet88's
two) over four draws of its search contacts.

    python reports/cross_sensor_label_free_codes/entry222/analyse.py

Reads `entry222/drawD/REG_seedK.json` (D = 0-3), the rows of `scripts/label_free_codes.py --search-draw D`,
per registry. Rule 1: draw 0 against entry 44's committed rows. Rule 2: per held-out unit, force RMSE over the
draws, max over min. Rule 3: each draw's figure against entry 165's three-start references, as entry 168 read
entry 44's. Rule 4: the lowest final objective's pick, and the validation units' spread. Read after: how far
apart the unit's network training alone would put four draws, and the codes' own spread.
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
ARM, METHOD = "joint_scale_encoder", "zero_shot"
REGISTRIES, DRAWS = ("other16", "fleet88"), (0, 1, 2, 3)
KEYS = ("force_rmse_n", "angle_rmse_rad")
Rows = dict[int, list[dict]]
RANGE = {2: 1.128, 3: 1.693, 4: 2.059}  # the expected range of n standard normal draws


def arm_rows(path: Path, arm: str = ARM) -> list[dict]:
    """One arm's rows of one run file (validation and held-out units)."""
    return [r for r in read_json(path)["rows"] if r["arm"] == arm]


def draws(registry: str) -> Rows:
    """{draw: every fold's rows} for the draws whose folds have all finished."""
    folds = E165["FOLDS"][registry]
    got = {d: [HERE / f"draw{d}" / f"{registry}_seed{k}.json" for k in folds] for d in DRAWS}
    done = {d: paths for d, paths in got.items() if all(p.exists() for p in paths)}
    return {d: [r for p in paths for r in arm_rows(p)] for d, paths in done.items()}


def entry44(registry: str, arm: str = ARM) -> dict[tuple[int, str], dict]:
    """(fold, unit) -> entry 44's row of the arm."""
    return {(r["seed"], r["unit"]): r for k in E165["FOLDS"][registry]
            for r in arm_rows(ENTRY44 / f"{registry}_seed{k}.json", arm)}


def gate(registry: str, today: list[dict]) -> None:
    """Rule 1: draw 0 against entry 44's rows, each unit's force and angle RMSE."""
    old = entry44(registry)
    ratio = {key: {f"{r['unit']} (fold {r['seed']})": r[key] / old[r["seed"], r["unit"]][key] for r in today}
             for key in KEYS}
    worst = max(abs(v - 1) for per in ratio.values() for v in per.values())
    verdict = "holds" if worst <= 1e-6 else "differs: draw 0 of this entry is the control"
    print(f"rule 1: draw 0 over entry 44's rows, largest relative difference {worst:.2e} over {len(today)} "
          f"units ({verdict})")
    for key, per in ratio.items():
        moved = np.abs(np.log(list(per.values())))
        far = max(per, key=lambda u: abs(np.log(per[u])))
        print(f"  {key}, draw 0 over entry 44's per unit: median |log| {np.median(moved):.3f}, "
              f"{int((moved > 1e-6).sum())} of {len(moved)} moved, farthest {far} x{per[far]:.3f}")


def by_unit(got: Rows, role: str, key: str) -> dict[str, list[float]]:
    """{'unit (fold)': [key per draw]} of the units of one role (a validation unit of two folds is two)."""
    out: dict[str, list[float]] = {}
    for d in sorted(got):
        for r in got[d]:
            if r["role"] == role:
                out.setdefault(f"{r['unit']} (fold {r['seed']})", []).append(r[key])
    return out


def spread(got: Rows, role: str) -> dict[str, float]:
    """Rule 2 (held out) and rule 4's second half (validation): max over min per unit; {key: median}."""
    medians = {}
    for key in KEYS:
        per = {u: max(v) / min(v) for u, v in by_unit(got, role, key).items()}
        worst = max(per, key=per.get)
        medians[key] = float(np.median(list(per.values())))
        print(f"  {role}, {key}: max over min per unit over {len(got)} draws, median x{medians[key]:.3f} "
              f"(largest x{per[worst]:.3f}, {worst}; {len(per)} units)")
    return medians


def separate(median: float) -> str:
    """Rule 2's reading of the held-out units' median force spread."""
    return "(H-design)" if median <= 1.04 else "(H-method)" if median >= 1.08 else "partly: between"


def against_references(registry: str, got: Rows) -> None:
    """Rule 3: each draw's held-out rows against the run's and the three-start references (entry 168)."""
    old = list(E165["old_references"](registry).values())
    new, _ = E165["new_references"](registry)
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


def objective_pick(got: Rows) -> None:
    """Rule 4: how often the draw of lowest final objective is the unit's draw of lowest force RMSE."""
    hits = n = 0
    for role in ("val", "test"):
        force = by_unit(got, role, "force_rmse_n")
        final = by_unit(got, role, f"objective_{ARM}")
        for u, f in force.items():
            hits += int(np.argmin([o[-1] for o in final[u]]) == np.argmin(f))
            n += 1
    print(f"  the lowest final objective picks the unit's best draw in force on {hits} of {n} units "
          f"(chance {n / len(got):.0f})")


def training_floor(registry: str, got: Rows) -> None:
    """Read after: how far apart draws would end from the unit's network training alone. The `encoder` arm's
    codes do not depend on the draw and equal entry 44's to 1e-4, yet its network, trained by today's code,
    moves from entry 44's; a range over the draws of that noise alone is about RANGE[n] standard deviations
    (the expected range of n normal draws). Beside it, the codes' own distance from the truth over the
    draws."""
    old = entry44(registry, "encoder")
    new = [r for k in E165["FOLDS"][registry] for r in arm_rows(HERE / "draw0" / f"{registry}_seed{k}.json",
                                                                  "encoder") if r["role"] == "test"]
    logs = [np.log(r["force_rmse_n"] / old[r["seed"], r["unit"]]["force_rmse_n"]) for r in new]
    sd = float(np.std(logs, ddof=1))
    span = np.exp(RANGE[len(got)] * sd)
    apart = [max(v) / min(v) for v in by_unit(got, "test", f"code_rms_{ARM}_off_truth").values()]
    print(f"  the encoder arm's force, today's network over entry 44's (the same codes): sd of log {sd:.3f} "
          f"over {len(logs)} units, so {len(got)} draws of training noise alone span about x{span:.3f}")
    print(f"  held-out codes' RMS distance from the truth, max over min over the draws: median "
          f"x{np.median(apart):.3f} (largest x{max(apart):.3f})")


def main() -> None:
    for registry in REGISTRIES:
        got = draws(registry)
        print(f"== {registry}: draws with all folds finished: {sorted(got)}")
        if 0 in got:
            gate(registry, got[0])
        if len(got) < 2:
            continue
        print("rule 2:")
        median = spread(got, "test")["force_rmse_n"]
        reading = separate(median) if len(got) == 4 else "two draws: read beside other16's over the same two"
        print(f"  reading: {reading}")
        if len(got) > 2:  # fleet88 stopped after two draws (the entry's amendment): the same two beside it
            print("  over draws 0 and 1 alone:")
            spread({d: got[d] for d in (0, 1)}, "test")
        print("rule 3:")
        against_references(registry, got)
        print("rule 4:")
        objective_pick(got)
        spread(got, "val")
        print("read after:")
        training_floor(registry, got)


if __name__ == "__main__":
    main()
