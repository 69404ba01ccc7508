"""One table of response models scored by `scripts/transfer_bounds.py` (each JSON the rows of one
model, `--response-model`), and paired comparisons of two models on the same held-out units
(research log entry 31):

    python scripts/response_model_table.py reports/cross_sensor_response_gpu/rows/*.json \\
        --pair fleet88_seed0_extra1024_rps32768:fleet88_seed0_extra128_rps4096

Per file and arm: the validation units' mean standardised MSE (the decision's statistic), the
held-out units' force and angle ratio to their references, mean over units with a 95% bootstrap
interval over units, and the mean test-patch pressure residual of the held-out units. A pair
`A:B` (file stems; `+` joins files, e.g. both folds) gives, over the held-out units both hold,
the geometric mean of A's ratio over B's per unit with its 95% bootstrap interval; a side
`STEMS@ARM` takes that arm's rows only, so two arms pair (`x@encoder:x@input_stats`).

Rows of `scripts/label_free_codes.py` (research log entry 35) have no validation loss: their
validation cell is the validation units' mean force and angle RMSE. `--pooled` adds each arm over
every file's rows together (e.g. all folds of a registry, or the validation units a rule names).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, ratio_text
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
        cells = [ratio_text(mean_interval([r[k] for r in held])) if held else "-" for k in KEYS[:2]]
        residual = [r["test_residual_pa"] for r in held if "test_residual_pa" in r]
        out.append(f"| {name} | {arm} | {validation(mine)} | {len(held)} | {' | '.join(cells)} | "
                   f"{f'{np.mean(residual):,.0f} Pa' if residual else '-'} |")
    return "\n".join(out)


def validation(rows: list[dict[str, Any]]) -> str:
    """The validation units' mean standardised MSE, or their mean force and angle RMSE."""
    val = [r for r in rows if r["role"] == "val"]
    if all("val_loss_mean" in r for r in val):
        return f"{np.mean([r['val_loss_mean'] for r in val]):.4f}"
    force, angle = (np.mean([r[k] for r in val]) for k in ("force_rmse_n", "angle_rmse_rad"))
    return f"{force:.3f} N / {angle:.4f} rad"


def side(files: dict[str, list[dict[str, Any]]], text: str) -> list[dict[str, Any]]:
    """The rows a pair's side names: `STEM+STEM...`, optionally `@ARM` (that arm's rows, arm unset)."""
    stems, _, arm = text.partition("@")
    rows = [r for stem in stems.split("+") for r in files[stem]]
    return [r | {"arm": ""} for r in rows if r["arm"] == arm] if arm else rows


def paired(a: list[dict[str, Any]], b: list[dict[str, Any]], key: str) -> str:
    """The geometric mean over shared held-out units of a's `key` over b's, [95% interval]."""
    ra = {(r["unit"], r["arm"]): r[key] for r in a if r["role"] == "test" and key in r}
    rb = {(r["unit"], r["arm"]): r[key] for r in b if r["role"] == "test" and key in r}
    ratios = [ra[k] / rb[k] for k in ra if k in rb]
    return f"{paired_text(ratios)} ({len(ratios)} units)" if ratios else "-"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rows", type=Path, nargs="+",
                        help="JSON files of transfer_bounds.py or label_free_codes.py")
    parser.add_argument("--pair", action="append", default=[],
                        help="A:B, file stems joined by +, each optionally @ARM")
    parser.add_argument("--pooled", action="store_true",
                        help="also one line per arm over every file's rows together (model `all`)")
    args = parser.parse_args(argv)
    files = rows_of(args.rows)
    print("| model | arm | validation | held-out units | force ratio [95%] | angle ratio [95%] | "
          "test residual |\n|---|---|---|---|---|---|---|")
    for name, rows in files.items():
        print(line(name, rows))
    if args.pooled:
        print(line("all", [r for rows in files.values() for r in rows]))
    for pair in args.pair:
        a, b = (side(files, text) for text in pair.split(":"))
        print(f"\n{pair}: " + "; ".join(f"{k} {paired(a, b, k)}" for k in KEYS))
    return 0


if __name__ == "__main__":
    sys.exit(main())
