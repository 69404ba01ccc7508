"""Research log entry 105's reading: fleet88's CPU rescoring with ordinary use, the plan's residual
correction on and off. Per method (`response@`, the plan alone; `response+use@`, with ordinary use) and
arm: the validation units' mean loss and the held-out ratios with the correction's per-unit factor; then
the rule's ratio of the correction's factor with ordinary use over its factor by the plan alone. Usage,
from the repository root:

    python reports/cross_sensor_response_gpu/entry105/analyse.py
"""

from pathlib import Path
from typing import Any

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
ARMS = ("on", "off")
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
METHODS = ("response@cover_informative", "response+use@cover_informative")
OVERLAP = 1.024  # half of a full overlap's 1 / 0.954 (the rule written down)


def folds() -> list[int]:
    """The folds both arms finished."""
    return [k for k in (0, 1) if all((run_dir(arm, k) / "metrics.json").exists() for arm in ARMS)]


def run_dir(arm: str, k: int) -> Path:
    return HERE / f"fleet88_cpu_use_{arm}" / f"fleet88_seed{k}"


def record(arm: str, k: int) -> dict[str, Any]:
    return read_json(run_dir(arm, k) / "provenance.json")["cross_sensor"][f"seed{k}"]


def per_unit(arm: str, key: str, method: str) -> dict[str, float]:
    """Each held-out unit's ratio to its per-unit reference in the arm's folds."""
    rows = [r for k in folds() for r in read_json(run_dir(arm, k) / "metrics.json")["results"]]
    return unit_ratios(rows, key)[(method, 120.0)]


def validation(method: str) -> str:
    losses = {arm: [record(arm, k)["val_loss"][method]["120"] for k in folds()] for arm in ARMS}
    on, off = (sum(v) / len(v) for v in losses.values())
    return f"validation on {on:.5f}, off {off:.5f} ({100 * (on / off - 1):+.2f}%)"


def main() -> None:
    print(f"folds: {folds()}")
    for method in METHODS:
        print(f"{method}, 120 s: {validation(method)}")
        for label, key in KEYS.items():
            on, off = per_unit("on", key, method), per_unit("off", key, method)
            (m, lo, hi), (c, clo, chi) = (mean_interval(list(p.values())) for p in (on, off))
            factor = paired_text([on[u] / off[u] for u in off])
            print(f"  held out {label}: on {m:.3f}x [{lo:.2f}, {hi:.2f}], off {c:.3f}x [{clo:.2f}, "
                  f"{chi:.2f}]; correction per unit x{factor} over {len(off)} units")
    for label, key in KEYS.items():
        gain = {m: {u: per_unit("on", key, m)[u] / r for u, r in per_unit("off", key, m).items()}
                for m in METHODS}
        alone, use = gain[METHODS[0]], gain[METHODS[1]]
        print(f"rule, {label}: the correction's factor with ordinary use over its factor alone "
              f"x{paired_text([use[u] / alone[u] for u in alone])} over {len(alone)} units "
              f"((E) below {OVERLAP} throughout, (F) above it throughout)")


if __name__ == "__main__":
    main()
