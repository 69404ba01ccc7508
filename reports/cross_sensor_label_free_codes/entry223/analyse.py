"""Research log entry 223: the label-free fit's contacts rescaled to the fleet's force scale (R,
`joint_scale_rescaled`) beside the fit as it ends (E, `joint_scale_encoder`), in the same invocations.

    python reports/cross_sensor_label_free_codes/entry223/analyse.py

Reads `entry223/drawD/REG_seedK_{val,all}.json`. Rule 1: R's contacts at the prior's mean square. Rule 2: the
decision on fleet88's validation units over draws 0-3. Rule 3, read after: held-out units at draw 0 (fleet88,
then other16) and the validation units' spread over the draws.
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

from anytip.rundir import read_json

HERE = Path(__file__).resolve().parent
E165 = runpy.run_path(str(HERE.parent.parent / "cross_sensor_response_gpu" / "entry165" / "analyse.py"))
geo = runpy.run_path(str(HERE.parent.parent / "cross_sensor_designs" / "entry219" / "analyse.py"))["geo"]
E, R, METHOD = "joint_scale_encoder", "joint_scale_rescaled", "zero_shot"
DRAWS, KEYS = (0, 1, 2, 3), ("force_rmse_n", "angle_rmse_rad")
Pairs = dict[tuple[int, int, str], tuple[dict, dict]]  # (draw, fold, unit) -> (E's row, R's row)


def pairs(registry: str, tag: str, role: str, draws: tuple[int, ...] = DRAWS) -> Pairs:
    """Each finished run's (E, R) rows of the units of one role."""
    out: Pairs = {}
    for d in draws:
        for k in E165["FOLDS"][registry]:
            path = HERE / f"draw{d}" / f"{registry}_seed{k}_{tag}.json"
            if not path.exists():
                continue
            rows = {(r["unit"], r["arm"]): r for r in read_json(path)["rows"] if r["role"] == role}
            out |= {(d, k, u): (rows[u, E], rows[u, R]) for u, a in rows if a == E}
    return out


def gate(rows: list[dict]) -> None:
    """Rule 1: R's contacts' mean square force equals the prior's mean on every row of R."""
    worst = max(abs(r[f"force_ms_{R}"] / r["force_ms_prior"] - 1) for r in rows)
    verdict = "holds" if worst <= 1e-4 else "fails"
    print(f"rule 1: R's mean square force over the prior's mean, largest relative difference {worst:.1e} "
          f"over {len(rows)} unit-draws ({verdict})")


def ratios(found: Pairs, key: str) -> list[float]:
    """R over E per unit-draw."""
    return [r[key] / e[key] for e, r in found.values()]


def decide(found: Pairs) -> None:
    """Rule 2: R over E on fleet88's validation units, geometric mean over unit-draws."""
    force, angle = (float(np.exp(np.mean(np.log(ratios(found, k))))) for k in KEYS)
    taken = force <= 0.98 and angle <= 1.01
    print(f"rule 2: R over E on {len(found)} validation unit-draws: force {geo(ratios(found, KEYS[0]))}, "
          f"angle {geo(ratios(found, KEYS[1]))}: {'taken' if taken else 'not taken'} (force <= x0.98, angle "
          "<= x1.01)")


def spread(found: Pairs) -> None:
    """The units' max over min over the draws, under E and under R."""
    for i, arm in enumerate((E, R)):
        per: dict[tuple[int, str], list[float]] = {}
        for (_, k, u), rows in found.items():
            per.setdefault((k, u), []).append(rows[i]["force_rmse_n"])
        apart = [max(v) / min(v) for v in per.values() if len(v) > 1]
        print(f"  {arm}: force max over min over the draws per unit, median x{np.median(apart):.3f} "
              f"(largest x{max(apart):.3f}, {len(apart)} units)")


def held_out(registry: str) -> None:
    """Rule 3: held-out units at draw 0, R over E per unit and each against three starts."""
    found = pairs(registry, "all", "test", (0,))
    if not found:
        print(f"  {registry}: no held-out run has finished")
        return
    print(f"  {registry}, {len(found)} held-out units at draw 0: R over E per unit, force "
          f"{geo(ratios(found, KEYS[0]))}, angle {geo(ratios(found, KEYS[1]))}")
    old = list(E165["old_references"](registry).values())
    new, _ = E165["new_references"](registry)
    for i, arm in enumerate((E, R)):
        shot = [{**rows[i], "method": METHOD, "budget_s": 0.0} for rows in found.values()]
        three, _ = E165["cell"](E165["swapped"](shot + old, new), METHOD, 0.0)
        print(f"    {arm} against three starts: {three}")
    fms = [e[f"force_ms_{E}"] / e["force_ms_truth"] for e, _ in found.values()]
    prior = [e["force_ms_prior"] / e["force_ms_truth"] for e, _ in found.values()]
    print(f"    E's mean square force over the truth: median {np.median(fms):.3f} ({min(fms):.3f}-"
          f"{max(fms):.3f}); the prior's over the truth: median {np.median(prior):.3f}")


def main() -> None:
    val = pairs("fleet88", "val", "val")
    tests = [p for reg in ("fleet88", "other16") for p in pairs(reg, "all", "test", (0,)).values()]
    gate([r for _, r in [*val.values(), *tests]])
    if val:
        decide(val)
    print("rule 3, read after:")
    held_out("fleet88")
    held_out("other16")
    if val:
        print("  fleet88's validation units over the draws:")
        spread(val)


if __name__ == "__main__":
    main()
