"""Research log entry 96's reading: do the validation units' decisions of entries 90-96 foresee the held-out
units? For each arm scored against its control on the same models (other16's default-spread models, four
folds; fleet88's CPU models, two): the validation units' mean loss alone at 120 s relative to the control's
(per fold and overall); the held-out units' force and angle RMSE paired per unit against the control's
(mean ratio [95% bootstrap interval over units]); and the held-out units' mean loss in the validation
loss's own terms (each unit's MSE over its five outputs, each output standardised by its training units'
standard deviation) relative to the control's. Whether the validation units' sign agrees with the
held-out units' loss separates two readings of a disagreement: the statistic (the validation loss weighs
the outputs otherwise than the force and angle figures) or the units (eight cannot resolve the change).
Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry96/concordance.py
"""

import importlib.util
from pathlib import Path

import numpy as np

from anytip.data.arrays import load_arrays
from anytip.data.registry import Registry
from anytip.report.cross_sensor import budget_of, mean_interval
from anytip.rundir import read_json

HERE = Path(__file__).parent
GPU = HERE.parent
E90 = GPU / "entry90"
OTHER16 = ("other16_seed", (0, 1, 2, 3), "data/other16")
FLEET88 = ("fleet88_seed", (0, 1), "data/fleet88")
BUDGET = 120.0  # s: the budget every table reads
OUTPUTS = ("fx_rmse", "fy_rmse", "fz_rmse", "theta_rmse", "phi_rmse")
CELLS = (E90 / "cover_informative_v", "cover_informative")
COVER = (GPU / "entry83" / "e60_d0", "cover")
FLEET88_COVER = (GPU / "entry86" / "fleet88_cpu_registry", "cover")
# (entry and arm, runs, control, arm)
PAIRS = (
    ("90 informative d", OTHER16, COVER, (E90 / "d", "informative")),
    ("90 informative v", OTHER16, COVER, (E90 / "v", "informative")),
    ("91 cover_informative d", OTHER16, COVER, (E90 / "cover_informative_d", "cover_informative")),
    ("91 cover_informative v", OTHER16, COVER, CELLS),
    ("92 one force level", OTHER16, CELLS, (E90 / "force_cells_v", "cover_informative")),
    ("93 low forces kept", OTHER16, CELLS, (E90 / "keep_low_v", "cover_informative")),
    ("94 drawn codes s=1", OTHER16, CELLS, (GPU / "entry94" / "scale1", "cover_informative")),
    ("94 drawn codes s=4", OTHER16, CELLS, (GPU / "entry94" / "scale4", "cover_informative")),
    ("95 press offsets", OTHER16, CELLS, (GPU / "entry94" / "offsets", "cover_informative")),
    ("96 weighted f", OTHER16, CELLS, (HERE / "f", "cover_informative")),
    ("96 weighted fp", OTHER16, CELLS, (HERE / "fp", "cover_informative")),
    ("90 fleet88 informative v", FLEET88, FLEET88_COVER, (E90 / "fleet88_cpu_v", "informative")),
    ("91 fleet88 cover_informative v", FLEET88, FLEET88_COVER,
     (E90 / "fleet88_cpu_cover_informative_v", "cover_informative")),
    ("94 fleet88 drawn codes s=1", FLEET88, FLEET88_COVER, (GPU / "entry94" / "fleet88_cpu_scale1", "cover")),
    ("96 fleet88 weighted fp", FLEET88, FLEET88_COVER, (HERE / "fleet88_cpu_fp", "cover")),
)


def entry90():
    """entry90/analyse.py as a module (its readers)."""
    spec = importlib.util.spec_from_file_location("entry90_analyse", E90 / "analyse.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def output_std(registry: str, root: Path, prefix: str, folds: tuple[int, ...]) -> dict[int, np.ndarray]:
    """Each fold's (5,) standard deviation of its training units' labels (their full-protocol runs)."""
    reg, out = Registry(registry, create=False), {}
    for k in folds:
        record = read_json(root / f"{prefix}{k}" / "provenance.json")["cross_sensor"][f"seed{k}"]
        train = set(record["units"]["train"])
        runs = [r for r in reg.list_runs() if r.unit in train and r.protocol == "full"]
        out[k] = load_arrays(reg, runs).targets.std(0)
    return out


def held_out_loss(root: Path, prefix: str, folds: tuple[int, ...], method: str,
                  std: dict[int, np.ndarray]) -> dict[str, float]:
    """{held-out unit: its standardised MSE at 120 s}, seeds averaged."""
    got: dict[str, list[float]] = {}
    for k in folds:
        for r in read_json(root / f"{prefix}{k}" / "metrics.json")["results"]:
            if r["method"] == method and budget_of(r) == BUDGET:
                err = np.array([r[o] for o in OUTPUTS]) / std[k]
                got.setdefault(r["unit"], []).append(float(np.mean(err**2)))
    return {u: float(np.mean(v)) for u, v in got.items()}


def main() -> None:
    t = entry90()
    print("arm | validation loss alone, per fold (%) | mean (%) | held out force | angle | "
          "held-out loss (%) | sign agrees with force and angle, with the held-out loss")
    agree, stds = [], {}
    for name, (prefix, folds, registry), (c_root, c_strat), (a_root, a_strat) in PAIRS:
        if not (t.done(c_root, prefix, folds) and t.done(a_root, prefix, folds)):
            continue
        if registry not in stds:
            stds[registry] = output_std(registry, c_root, prefix, folds)
        c = np.array(t.val_losses(c_root, prefix, folds, f"response@{c_strat}"))
        a = np.array(t.val_losses(a_root, prefix, folds, f"response@{a_strat}"))
        per_fold = " ".join(f"{v:+.1f}" for v in 100 * (a / c - 1))
        val = 100 * (a.mean() / c.mean() - 1)
        held = []
        for key in t.KEYS.values():
            base = t.per_unit(c_root, prefix, folds, f"response@{c_strat}", key)
            mine = t.per_unit(a_root, prefix, folds, f"response@{a_strat}", key)
            held.append(mean_interval([mine[u] / base[u] for u in base]))
        both = float(np.sqrt(held[0][0] * held[1][0]))
        c_loss = held_out_loss(c_root, prefix, folds, f"response@{c_strat}", stds[registry])
        a_loss = held_out_loss(a_root, prefix, folds, f"response@{a_strat}", stds[registry])
        loss = 100 * (np.mean([a_loss[u] for u in c_loss]) / np.mean(list(c_loss.values())) - 1)
        same = (bool(np.sign(val) == np.sign(both - 1)), bool(np.sign(val) == np.sign(loss)))
        agree.append((abs(val), same))
        print(f"{name} | {per_fold} | {val:+.1f} | " + " | ".join(f"x{m:.3f} [{lo:.3f}, {hi:.3f}]"
                                                                     for m, lo, hi in held)
              + f" | {loss:+.1f} | {'yes' if same[0] else 'no'} (x{both:.3f}), {'yes' if same[1] else 'no'}")
    for lo, hi in ((0, 5), (5, 100)):
        got = [s for v, s in agree if lo <= v < hi]
        ratio, loss = sum(s[0] for s in got), sum(s[1] for s in got)
        print(f"|validation change| in [{lo}, {hi})%, {len(got)} arms: the sign agrees with the held-out "
              f"force and angle in {ratio}, with the held-out loss in {loss}")


if __name__ == "__main__":
    main()
