"""Research log entry 191's reading: rule 1 (S and H read the same rows), then log(S / H) per fresh validation
unit, force and angle, over all 64 and per elastomer (geometric means with 95% t-intervals), each network of
build/entry191/ARM-FOLD/UNIT scored on its unit's three full runs as entries 183-190 scored theirs. Entry 192
reads its arms with the same functions.

    python reports/cross_sensor_response_gpu/entry191/score.py > \\
        reports/cross_sensor_response_gpu/entry191/logs/score.log
"""

from __future__ import annotations

import json
import runpy
from pathlib import Path

import numpy as np

from anytip.data.registry import Registry

HERE = Path(__file__).parent
E178 = runpy.run_path(str(HERE.parent / "entry178" / "score.py"))
interval = runpy.run_path(str(HERE.parent / "entry183" / "score.py"))["interval"]
PAIRS = runpy.run_path(str(HERE / "units.py"))["PAIRS"]
GROUPS = (("all 64", "fo"), ("default fingertip's 32 (SIM41)", "f"), ("other elastomer's 32 (SIM24)", "o"))


def same_rows(roots: dict[str, Path], pairs: list[tuple[str, str]] = PAIRS) -> str:
    """Rule 1: how many of `pairs`' units' two arms (`roots`: arm -> the directory of its ARM-FOLD/UNIT
    networks) read the same rows of their logs, and the contact seconds the first read."""
    def record(arm: str, fold: str, unit: str) -> dict:
        return json.loads((roots[arm] / f"{arm}-{fold}" / unit / "calibration.json").read_text())
    arms = list(roots)
    rows = {a: [record(a, f, u)["unlabeled_samples"] for f, u in pairs] for a in arms}
    same = sum(x == y for x, y in zip(*rows.values(), strict=True))
    held = [record(arms[0], f, u)["unlabeled_seconds"] for f, u in pairs]
    return (f"rule 1: {' and '.join(arms)} read the same rows for {same} of {len(pairs)} units "
            f"({min(held):.1f}-{max(held):.1f} contact-s)")


def scored(roots: dict[str, Path], pairs: list[tuple[str, str]] = PAIRS
           ) -> dict[tuple[str, str, str], dict[str, float]]:
    """Each arm's network (`roots`: arm -> the directory of its ARM-FOLD/UNIT networks) per (arm, fold, unit)
    of `pairs` on the unit's full runs: {force_rmse_n, angle_rmse_rad}."""
    registries = {"f": Registry("data/val191d"), "o": Registry("data/val191o")}
    return {(a, f, u): E178["scored"](registries[f[0]], u, f"{a}-{f}", root)
            for a, root in roots.items() for f, u in pairs}


def ratio_table(rmse: dict[tuple[str, str, str], dict[str, float]], top: str, bottom: str,
                dump: bool = True, groups: tuple[tuple[str, str], ...] = GROUPS) -> None:
    """`top` over `bottom` per unit, force and angle, per group of GROUPS: a markdown table, then (`dump`)
    every arm's RMSEs as JSON."""
    print("| units | force | angle |")
    print("|---|---|---|")
    for name, keep in groups:
        chosen = [(f, u) for f, u in PAIRS if f[0] in keep]
        cells = [interval([np.log(rmse[top, f, u][k] / rmse[bottom, f, u][k]) for f, u in chosen])
                 for k in E178["OUTPUTS"]]
        print(f"| {name} | " + " | ".join(cells) + " |")
    if dump:
        print("\n" + json.dumps({f"{a} {f} {u}": v for (a, f, u), v in rmse.items()}))


def main() -> None:
    roots = dict.fromkeys("SH", Path("build/entry191"))
    print(same_rows(roots))
    print("\nrule 2, S (weighed as 600 s) over H (as held), per fresh validation unit")
    ratio_table(scored(roots), "S", "H")


if __name__ == "__main__":
    main()
