"""Research log entry 83's tables: the start network's draws at 60 and 240 epochs on other16's four
folds (`e{EPOCHS}_d{DRAW}/other16_seed{K}`), fleet88 fold 0's four draws (entry 81's control and
entry 52's start network, `fleet88_d{1,2}`), and other16 with entry 80's severe model over three
draws (`severe_d{DRAW}`). Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry83/analyse.py
"""

import functools
import re
from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, summary, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
ARMS, DRAWS, FOLDS = ("e60", "e240"), (0, 1, 2), (0, 1, 2, 3)
METHODS = ("response+use@cover", "response@cover")
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}


def run(a: str, d: int, k: int) -> Path:
    """Arm a's (`e60`, `e240`, `severe`) rescoring of fold k with draw d."""
    return HERE / f"{a}_d{d}" / f"other16_seed{k}"


BUDGET = 120.0  # robot seconds of every rescored row


@functools.cache
def rows(a: str, d: int, k: int) -> list[dict[str, Any]]:
    """The rows of one rescoring."""
    return read_json(run(a, d, k) / "metrics.json")["results"]


@functools.cache
def losses(a: str, d: int, k: int) -> dict[str, dict[str, float]]:
    """{method: {budget: the validation units' loss}} of one rescoring."""
    return read_json(run(a, d, k) / "provenance.json")["cross_sensor"][f"seed{k}"]["val_loss"]


def val_loss(a: str, d: int, k: int, method: str) -> float:
    return losses(a, d, k)[method]["120"]


def start_loss(a: str, d: int, k: int) -> float:
    text = (HERE / "logs" / f"{a}_d{d}_seed{k}.txt").read_text()
    return float(re.search(r"best val_loss ([0-9.eE+-]+)", text).group(1))


def ratios(runs: list[tuple[str, int, int]], method: str, key: str) -> dict[str, float]:
    """{held-out unit: its `key` averaged over the runs that score it, over its per-unit reference's}
    (`unit_ratios`: the runs are draws of the same units, seeds and references)."""
    return unit_ratios([r for run_ in runs for r in rows(*run_)], key)[(method, BUDGET)]


def every_draw(a: str) -> list[tuple[str, int, int]]:
    return [(a, d, k) for k in FOLDS for d in DRAWS]


def spread(a: str, method: str) -> tuple[float, list[float], list[list[float]]]:
    """(pooled within-fold deviation over draws of the fold's mean force ratio, the 16-unit mean of
    each draw, [fold][draw] fold means)."""
    folds = [[float(np.mean(list(ratios([(a, d, k)], method, "force_rmse_n").values()))) for d in DRAWS]
             for k in FOLDS]
    pooled = float(np.sqrt(np.mean([np.var(m, ddof=1) for m in folds])))
    whole = [float(np.mean([folds[k][d] for k in FOLDS])) for d in DRAWS]  # 4 units a fold
    return pooled, whole, folds


ENTRY81 = HERE.parent / "entry81"
FLEET88 = {"draw 0 (entry 81's control, 10 steps)": ENTRY81 / "fleet88_it10/fleet88_seed0",
           "entry 52's start network (entry 81, 30 steps)": ENTRY81 / "fleet88_start52/fleet88_seed0",
           "draw 1": HERE / "fleet88_d1/fleet88_seed0", "draw 2": HERE / "fleet88_d2/fleet88_seed0"}


def fleet88() -> None:
    """fleet88 fold 0's 44-unit mean per draw of the start network, their deviation and range."""
    means: dict[str, list[tuple[float, float]]] = {m: [] for m in METHODS}
    for name, path in FLEET88.items():
        lines = {s["method"]: s for s in summary(read_json(path / "metrics.json")["results"])}
        for m in METHODS:
            force, angle = lines[m]["force_unit"], lines[m]["angle_unit"]
            means[m].append((force[0], angle[0]))
            print(f"fleet88 fold 0, {name}, {m}: {force[0]:.3f}x [{force[1]:.2f}, {force[2]:.2f}]"
                  f" / {angle[0]:.3f}x")
    for m, values in means.items():
        f, a = np.array(values).T
        print(f"{m}: force deviation {np.std(f, ddof=1):.4f}, range {f.min():.3f}-{f.max():.3f}; "
              f"angle deviation {np.std(a, ddof=1):.4f}, range {a.min():.3f}-{a.max():.3f}")


def arm_lines(a: str, method: str) -> float:
    """Print arm a's spread, validation losses and draw-averaged figures; return its pooled deviation."""
    dev, whole, folds = spread(a, method)
    vals = [np.mean([val_loss(a, d, k, method) for k in FOLDS]) for d in DRAWS]
    print(f"{a}: pooled deviation {dev:.4f}; 16-unit mean per draw " + ", ".join(f"{w:.3f}" for w in whole)
          + "; validation loss per draw " + ", ".join(f"{v:.5f}" for v in vals)
          + f" (mean {np.mean(vals):.5f})")
    for k in FOLDS:
        print(f"  fold {k}: held-out mean per draw " + ", ".join(f"{m:.3f}" for m in folds[k])
              + "; start network's val loss " + ", ".join(f"{start_loss(a, d, k):.5f}" for d in DRAWS)
              + "; validation units' loss " + ", ".join(f"{val_loss(a, d, k, method):.5f}" for d in DRAWS))
    for name, key in KEYS.items():
        per = ratios(every_draw(a), method, key)
        m, lo, hi = mean_interval(list(per.values()))
        print(f"  {name}: draw-averaged {m:.3f}x [{lo:.2f}, {hi:.2f}] over {len(per)} units")
    return dev


def main() -> None:
    for method in METHODS:
        print(f"## {method}, 120 s")
        dev = {a: arm_lines(a, method) for a in ARMS}
        print(f"deviation ratio 240/60: {dev['e240'] / dev['e60']:.2f}")
        for name, key in KEYS.items():
            per = {a: ratios(every_draw(a), method, key) for a in ARMS}  # the same references
            paired = [per["e240"][u] / per["e60"][u] for u in per["e60"]]
            print(f"paired 240 over 60, {name}: x{paired_text(paired)}")
        if all((run("severe", d, k) / "metrics.json").is_file() for d in DRAWS for k in FOLDS):
            arm_lines("severe", method)
        print()
    if all((p / "metrics.json").is_file() for p in FLEET88.values()):
        fleet88()

if __name__ == "__main__":
    main()
