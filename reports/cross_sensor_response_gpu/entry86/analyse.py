"""Research log entry 86's tables: other16's four folds rescored with each code prior
(`{PRIOR}/other16_seed{K}`) against entry 83's `e60_d0` (the control before the code change), and
fleet88 fold 0 where it ran (`fleet88_{PRIOR}/fleet88_seed0`). Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry86/analyse.py
"""

import functools
from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
CONTROL = HERE.parent / "entry83" / "e60_d0"
PRIORS, FOLDS, BUDGET = ("diagonal", "barometer", "registry"), (0, 1, 2, 3), 120.0
METHODS = ("response@cover", "response+use@cover")
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}


def fold_run(arm: str, k: int) -> Path:
    """Arm `control` (entry 83's e60_d0) or a prior's rescoring of other16 fold k."""
    return (CONTROL if arm == "control" else HERE / arm) / f"other16_seed{k}"


@functools.cache
def rows(path: Path) -> list[dict[str, Any]]:
    return read_json(path / "metrics.json")["results"]


def val_loss(path: Path, seed: int, method: str) -> float:
    """The validation units' loss of `method` at 120 s in one run."""
    return read_json(path / "provenance.json")["cross_sensor"][f"seed{seed}"]["val_loss"][method]["120"]


def ratios(paths: list[Path], method: str, key: str) -> dict[str, float]:
    """{held-out unit: its `key` over its per-unit reference's} at 120 s over the runs' units."""
    return unit_ratios([r for p in paths for r in rows(p)], key)[(method, BUDGET)]


def other16_table() -> None:
    done = [p for p in PRIORS if all((fold_run(p, k) / "metrics.json").is_file() for k in FOLDS)]
    arms = ["control", *done]
    control = {m: {n: ratios([fold_run("control", k) for k in FOLDS], m, key) for n, key in KEYS.items()}
               for m in METHODS}
    for a in arms:
        paths = [fold_run(a, k) for k in FOLDS]
        for m in METHODS:
            loss = np.mean([val_loss(p, k, m) for k, p in zip(FOLDS, paths, strict=True)])
            base = np.mean([val_loss(fold_run("control", k), k, m) for k in FOLDS])
            line = f"{a:9s} {m:20s} val {loss:.5f} ({100 * (loss / base - 1):+.1f}%)"
            for n, key in KEYS.items():
                per = ratios(paths, m, key)
                mean, lo, hi = mean_interval(list(per.values()))
                paired = [per[u] / control[m][n][u] for u in per]
                line += f" | {n} {mean:.3f}x [{lo:.2f}, {hi:.2f}] paired x{paired_text(paired)}"
                if a == "diagonal":
                    line += f" max dev {max(abs(r - 1) for r in paired):.1e}"
            print(line)


def fleet88_table() -> None:
    """fleet88 fold 0 against entry 81's 10-step arm (draw 0, the same model and recipe)."""
    base = HERE.parent / "entry81" / "fleet88_it10" / "fleet88_seed0"
    for p in PRIORS:
        path = HERE / f"fleet88_{p}" / "fleet88_seed0"
        if not (path / "metrics.json").is_file():
            continue
        for m in METHODS:
            loss, before = val_loss(path, 0, m), val_loss(base, 0, m)
            line = f"fleet88 {p:9s} {m:20s} val {loss:.5f} ({100 * (loss / before - 1):+.1f}%)"
            for n, key in KEYS.items():
                per, ref = ratios([path], m, key), ratios([base], m, key)
                mean, lo, hi = mean_interval(list(per.values()))
                paired = paired_text([per[u] / ref[u] for u in per])
                line += f" | {n} {mean:.3f}x [{lo:.2f}, {hi:.2f}] paired x{paired}"
            print(line)


DRAWS = (0, 1, 2)
SEVERE = {"diagonal": HERE.parent / "entry83" / "severe_d{d}", "registry": HERE / "severe_registry_d{d}"}


def severe_table() -> None:
    """Rule 6: the severe model over three draws of the start network, per prior: mean validation
    loss over draws and folds, and the draw-averaged ratios of the 16 held-out units."""
    paths = {p: [Path(str(t).format(d=d)) / f"other16_seed{k}" for d in DRAWS for k in FOLDS]
             for p, t in SEVERE.items()}
    if not all((q / "metrics.json").is_file() for ps in paths.values() for q in ps):
        return
    for m in METHODS:
        per = {p: {n: ratios(ps, m, key) for n, key in KEYS.items()} for p, ps in paths.items()}
        for p, ps in paths.items():
            loss = np.mean([val_loss(q, int(q.name[-1]), m) for q in ps])
            line = f"severe {p:9s} {m:20s} val {loss:.5f}"
            for n in KEYS:
                mean, lo, hi = mean_interval(list(per[p][n].values()))
                paired = paired_text([per[p][n][u] / per["diagonal"][n][u] for u in per[p][n]])
                line += f" | {n} {mean:.3f}x [{lo:.2f}, {hi:.2f}] paired x{paired}"
            print(line)


BUDGETS = HERE.parent.parent / "cross_sensor_budgets"


def both_folds_table(name: str, control: list[Path], registry: list[Path], methods: tuple[str, ...]) -> None:
    """fleet88's two folds: validation loss per fold, the 88 units under each prior, paired per unit."""
    if not all((p / "metrics.json").is_file() for p in registry):
        return
    for m in methods:
        losses = [f"fold {k} {val_loss(r, k, m):.5f} against {val_loss(c, k, m):.5f}"
                  for k, (c, r) in enumerate(zip(control, registry, strict=True))]
        print(f"{name} {m}: validation " + ", ".join(losses))
        for n, key in KEYS.items():
            per, ref = ratios(registry, m, key), ratios(control, m, key)
            a, alo, ahi = mean_interval(list(per.values()))
            b, blo, bhi = mean_interval(list(ref.values()))
            print(f"  {n}: registry {a:.3f}x [{alo:.2f}, {ahi:.2f}], "
                  f"diagonal {b:.3f}x [{blo:.2f}, {bhi:.2f}], "
                  f"paired x{paired_text([per[u] / ref[u] for u in ref])} over {len(ref)} units")


if __name__ == "__main__":
    other16_table()
    fleet88_table()
    severe_table()
    gpu = [HERE.parent / "entry81" / "fleet88_it10" / "fleet88_seed0",
           HERE / "fleet88_diagonal" / "fleet88_seed1"]
    mine = [HERE / "fleet88_registry" / f"fleet88_seed{k}" for k in (0, 1)]
    both_folds_table("fleet88, 1,024-unit models", gpu, mine, METHODS)
    cpu = [HERE / "fleet88_cpu_registry" / f"fleet88_seed{k}" for k in (0, 1)]
    both_folds_table("fleet88, CPU models (128 simulated units)",
                     [BUDGETS / f"fleet88_grouped_seed{k}" for k in (0, 1)], cpu, ("response@cover",))
