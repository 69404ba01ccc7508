"""Research log entry 121's reading: other16's designed plan with today's recipe, `cover_informative` beside
it in the same runs. Rule 1 as amended: the references' rows and each shared method's plans equal entry
101's run of the same fold and draw; the shared methods' RMSEs move by the code's drift since then, which is
reported. Rule 2: the designed plan's ratios at 120 s, each unit's draws averaged, with and without ordinary
use. Rule 3: designed over `cover_informative`, paired per unit. Reads the draws whose four folds ran.
Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry121/analyse.py
"""

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
BEFORE = HERE.parent / "entry101"
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
FOLDS = (0, 1, 2, 3)
SHARED = ("response@cover_informative", "response+use@cover_informative")
METHODS = tuple(f"{use}@{plan}" for use in ("response+use", "response")
                for plan in ("designed", "cover_informative"))


def run_dir(root: Path, d: int, k: int) -> Path:
    return root / f"other16_severe_d{d}" / f"other16_seed{k}"


def rows(root: Path, d: int, k: int) -> list[dict[str, Any]]:
    return read_json(run_dir(root, d, k) / "metrics.json")["results"]


def record(root: Path, d: int, k: int) -> dict[str, Any]:
    return read_json(run_dir(root, d, k) / "provenance.json")["cross_sensor"][f"seed{k}"]


def data_check(new: list[dict[str, Any]], old: list[dict[str, Any]], shared: Sequence[str]
               ) -> tuple[bool, int, float]:
    """Rule 1's reading of two runs' rows (entry 122's too): whether their references' rows and the `shared`
    methods' plans are equal, how many RMSEs of those methods they hold, and the most any moved (relative)."""
    def plans(got: list[dict[str, Any]]) -> list[tuple[Any, ...]]:
        return sorted((r["method"], r["unit"], r["seed"], r["calib_samples"], r["calib_seconds"])
                      for r in got if r["method"] in shared)

    def references(got: list[dict[str, Any]]) -> list[tuple[Any, ...]]:
        return sorted(tuple(sorted(r.items())) for r in got if r["method"] == "per_unit")

    def rmses(got: list[dict[str, Any]]) -> np.ndarray:
        return np.array([r[key] for r in sorted(got, key=lambda r: (r["method"], r["unit"]))
                         if r["method"] in shared for key in KEYS.values()])

    equal = plans(new) == plans(old) and references(new) == references(old)
    moved = rmses(new) / rmses(old) - 1
    return equal, len(moved), float(np.max(np.abs(moved)))


def same_data(d: int, k: int) -> None:
    """Rule 1 against entry 101's run of the same draw and fold: the data's identity, and how far the
    shared methods' RMSEs moved (the code's drift)."""
    equal, n, drift = data_check(rows(HERE, d, k), rows(BEFORE, d, k), SHARED)
    print(f"rule 1, draw {d}, fold {k}: references and plans {'equal' if equal else 'DIFFER'}; "
          f"the shared methods' {n} RMSEs move by up to {drift:.3f} relative")


def at_120(got: list[dict[str, Any]], method: str) -> dict[str, dict[str, float]]:
    """Per output kind, per unit: the method's ratio at 120 s in rows `got`, the unit's seeds and
    draws averaged (entry 122 reads it too)."""
    return {label: unit_ratios(got, key)[(method, 120.0)] for label, key in KEYS.items()}


def unit_figure(root: Path, draws: list[int], method: str) -> dict[str, dict[str, float]]:
    """`at_120` over the draws' runs under root."""
    return at_120([r for d in draws for k in FOLDS for r in rows(root, d, k)], method)


def line(per: dict[str, dict[str, float]]) -> str:
    """Each output kind's mean over units with its 95% interval (entry 122 reads it too)."""
    parts = []
    for label in KEYS:
        m, lo, hi = mean_interval(list(per[label].values()))
        parts.append(f"{label} {m:.3f}x [{lo:.2f}, {hi:.2f}]")
    return ", ".join(parts) + f" over {len(per['force'])} units"


def designed_over_informative(per: dict[str, dict[str, dict[str, float]]]) -> None:
    """Rule 3 (entry 122's too): designed over `cover_informative` per unit, with and without use, from
    `at_120`'s figures of each method in `per`."""
    print("rule 3, designed over cover_informative, paired per unit:")
    for use in ("response+use", "response"):
        d, c = per[f"{use}@designed"], per[f"{use}@cover_informative"]
        paired = {label: paired_text([d[label][u] / c[label][u] for u in c[label]]) for label in KEYS}
        print(f"  {use}: " + ", ".join(f"{label} x{text}" for label, text in paired.items()))


def main() -> None:
    draws = [d for d in (0, 1, 2) if all((run_dir(HERE, d, k) / "metrics.json").is_file() for k in FOLDS)]
    for d in draws:
        for k in FOLDS:
            same_data(d, k)
    print(f"rule 2, draws {draws}, 120 s:")
    per = {m: unit_figure(HERE, draws, m) for m in METHODS}
    for m in METHODS:
        print(f"  {m}: {line(per[m])}")
    for m in SHARED:
        print(f"  entry 101's {m}, the same draws: {line(unit_figure(BEFORE, draws, m))}")
    designed_over_informative(per)
    for d in draws:
        val = {m: np.mean([record(HERE, d, k)["val_loss"][m]["120"] for k in FOLDS]) for m in METHODS}
        means = ", ".join(f"{m} {v:.5f}" for m, v in val.items())
        print(f"validation, draw {d}, mean over the folds: {means}")


if __name__ == "__main__":
    main()
