"""One table of response models scored by `scripts/transfer_bounds.py` (each JSON the rows of one
model, `--response-model`), and paired comparisons of two models on the same held-out units
(research log entry 31):

    python scripts/response_model_table.py reports/cross_sensor_response_gpu/rows/*.json \\
        --pair fleet88_seed0_extra1024_rps32768:fleet88_seed0_extra128_rps4096

Per file and arm: the validation units' mean standardised MSE (the decision's statistic), the
held-out units' force and angle ratio to their references, mean over units with a 95% bootstrap
interval over units, and the mean test-patch pressure residual of the held-out units. A pair
`A:B` (file stems; `+` joins files, e.g. both folds) gives, over the held-out units both hold,
the geometric mean of A's ratio over B's per unit with its 95% bootstrap interval.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, ratio_text
from anytip.rundir import read_json

KEYS = ("force_ratio", "angle_ratio", "test_residual_pa")


def rows_of(paths: list[Path]) -> dict[str, list[dict[str, Any]]]:
    """{file stem: its rows}."""
    return {p.stem: read_json(p)["rows"] for p in paths}


def line(name: str, rows: list[dict[str, Any]]) -> str:
    """A table row per arm of one file."""
    out = []
    for arm in sorted({r["arm"] for r in rows}):
        mine = [r for r in rows if r["arm"] == arm]
        held = [r for r in mine if r["role"] == "test"]
        val = [r["val_loss_mean"] for r in mine if r["role"] == "val"]
        cells = [ratio_text(mean_interval([r[k] for r in held])) for k in KEYS[:2]]
        out.append(f"| {name} | {arm} | {np.mean(val):.4f} | {len(held)} | {' | '.join(cells)} | "
                   f"{np.mean([r['test_residual_pa'] for r in held]):,.0f} Pa |")
    return "\n".join(out)


def paired(a: list[dict[str, Any]], b: list[dict[str, Any]], key: str) -> str:
    """The geometric mean over shared held-out units of a's `key` over b's, [95% interval]."""
    ra = {(r["unit"], r["arm"]): r[key] for r in a if r["role"] == "test"}
    rb = {(r["unit"], r["arm"]): r[key] for r in b if r["role"] == "test"}
    logs = [float(np.log(ra[k] / rb[k])) for k in ra if k in rb]
    m, lo, hi = (float(np.exp(v)) for v in mean_interval(logs))
    return f"{m:.3f} [{lo:.3f}, {hi:.3f}] ({len(logs)} units)"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rows", type=Path, nargs="+", help="transfer_bounds.py JSON files")
    parser.add_argument("--pair", action="append", default=[], help="A:B, file stems joined by +")
    args = parser.parse_args(argv)
    files = rows_of(args.rows)
    print("| model | arm | validation loss | held-out units | force ratio [95%] | angle ratio [95%] | "
          "test residual |\n|---|---|---|---|---|---|---|")
    for name, rows in files.items():
        print(line(name, rows))
    for pair in args.pair:
        a, b = ([r for stem in side.split("+") for r in files[stem]] for side in pair.split(":"))
        print(f"\n{pair}: " + "; ".join(f"{k} {paired(a, b, k)}" for k in KEYS))
    return 0


if __name__ == "__main__":
    sys.exit(main())
