"""Research log entry 124's reading: fleet88's designed plan with the plan's residual correction off (this
entry) and on (entry 122). Rule 1, the choice on validation units: (a) fleet88's 8 validation units' mean
loss of `response+use@designed` at 120 s, off against on; (b) over the 16 validation units of both
registries (other16's, entries 123 off and 121 on, each unit's three draws averaged in log), the mean of
log(off / on) with its 95% t-interval. Rule 2, read after: fleet88's held-out units off over on per unit
for every method, and `cover_informative` off against entry 105's off arm. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry124/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np
from scipy import stats

HERE = Path(__file__).parent
GPU = HERE.parent
FLEET88 = runpy.run_path(str(GPU / "entry122" / "analyse.py"))
OTHER16 = runpy.run_path(str(GPU / "entry121" / "analyse.py"))
PAIRING = runpy.run_path(str(GPU / "entry123" / "analyse.py"))  # its off_over_on
METHOD = "response+use@designed"
KEYS, METHODS = FLEET88["KEYS"], FLEET88["METHODS"]


def fleet88_losses(root: Path, method: str = METHOD) -> dict[tuple[int, str], float]:
    """Each fleet88 validation unit's loss of `method` at 120 s, per fold (both folds)."""
    return {(k, u): v for k in FLEET88["FOLDS"]
            for u, v in FLEET88["record"](root, k)["val_loss_units"][method]["120"].items()}


def other16_logs(new: Path = GPU / "entry123", old: Path = GPU / "entry121") -> dict[tuple[int, str], float]:
    """Each other16 validation unit's log(new / old) of METHOD at 120 s, per fold (a unit may validate two
    folds: SIM23-004 does, in folds 0 and 2), its three draws averaged."""
    logs: dict[tuple[int, str], list[float]] = {}
    for d in (0, 1, 2):
        for k in OTHER16["FOLDS"]:
            off = OTHER16["record"](new, d, k)["val_loss_units"][METHOD]["120"]
            on = OTHER16["record"](old, d, k)["val_loss_units"][METHOD]["120"]
            for u in on:
                logs.setdefault((k, u), []).append(float(np.log(off[u] / on[u])))
    return {key: float(np.mean(v)) for key, v in logs.items()}


def choice(fleet88: Path = HERE, other16: Path = GPU / "entry123", arm: str = "off", by: float = 0.0,
           recipe: tuple[Path, Path] = (GPU / "entry122", GPU / "entry121")) -> bool:
    """Rule 1: arm `arm` (fleet88's run under `fleet88`, other16's under `other16`) against the recipe in
    place (`recipe`: its fleet88 and other16 runs, entries 122 and 121 here): (a) fleet88's validation mean
    lower by more than `by`; (b) both registries' log ratios' 95% t-interval below 0 (entries 131 and 133
    read it too)."""
    off, on = fleet88_losses(fleet88), fleet88_losses(recipe[0])
    m_off, m_on = np.mean(list(off.values())), np.mean(list(on.values()))
    lower = m_off < m_on * (1 - by)
    print(f"rule 1a, fleet88's {len(on)} validation units, {METHOD}: {arm} {m_off:.5f}, on {m_on:.5f} "
          f"({100 * (m_off / m_on - 1):+.2f}%): {f'lower {arm}' if lower else f'not lower {arm}'}")
    logs = [float(np.log(off[u] / on[u])) for u in on] + list(other16_logs(other16, recipe[1]).values())
    mean, sem = float(np.mean(logs)), float(stats.sem(logs))
    lo, hi = stats.t.interval(0.95, len(logs) - 1, loc=mean, scale=sem)
    print(f"rule 1b, {len(logs)} validation units of both registries: mean log({arm} / on) {mean:+.4f} "
          f"[{lo:+.4f}, {hi:+.4f}] (x{np.exp(mean):.3f} [{np.exp(lo):.3f}, {np.exp(hi):.3f}]): "
          f"{'below 0' if hi < 0 else 'not below 0'}")
    print(f"the choice: {'taken' if lower and hi < 0 else 'not taken'}")
    return bool(lower and hi < 0)


def held_out(fleet88: Path = HERE, arm: str = "off", recipe: Path = GPU / "entry122") -> None:
    """Rule 2: fleet88's held-out units, `arm` under `fleet88` over the recipe's run under `recipe` (entry
    122 here) per unit for every method."""
    print(f"rule 2, fleet88's held-out units, 120 s, {arm} over on per unit:")
    for m in METHODS:
        off, on = FLEET88["unit_figure"](fleet88, m), FLEET88["unit_figure"](recipe, m)
        print(f"  {m}: {PAIRING['off_over_on'](off, on, arm)}")


if __name__ == "__main__":
    choice()
    held_out()
    before = FLEET88["unit_figure"](GPU / "entry105" / "fleet88_cpu_use_off", METHODS[1])
    print(f"  entry 105's off arm, {METHODS[1]}: {FLEET88['line'](before)}")
