"""Research log entry 87's table: other16's plan alone with oracle codes (`oracle/other16_seed{K}`)
against entry 83's `e60_d0`, alone and with ordinary use. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry87/analyse.py
"""

from pathlib import Path

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
CONTROL, ORACLE = HERE.parent / "entry83" / "e60_d0", HERE / "oracle"
FOLDS, BUDGET = (0, 1, 2, 3), 120.0
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}


def per_unit(root: Path, method: str, key: str) -> dict[str, float]:
    """{held-out unit: ratio} of `method` at 120 s over the four folds under root."""
    rows = [r for k in FOLDS for r in read_json(root / f"other16_seed{k}" / "metrics.json")["results"]]
    return unit_ratios(rows, key)[(method, BUDGET)]


def main() -> None:
    for name, key in KEYS.items():
        alone = per_unit(CONTROL, "response@cover", key)
        use = per_unit(CONTROL, "response+use@cover", key)
        oracle = per_unit(ORACLE, "response@cover", key)
        for label, per in (("plan alone", alone), ("with use", use), ("oracle codes", oracle)):
            m, lo, hi = mean_interval(list(per.values()))
            print(f"{name} {label:12s} {m:.3f}x [{lo:.2f}, {hi:.2f}]")
        print(f"{name} oracle over plan alone x{paired_text([oracle[u] / alone[u] for u in alone])}; "
              f"over with use x{paired_text([oracle[u] / use[u] for u in use])}; "
              f"with use over plan alone x{paired_text([use[u] / alone[u] for u in alone])}")


if __name__ == "__main__":
    main()
