"""Research log entry 161's reading: folds 0 and 1's fresh units given references tried at the learning rates
0.01 and 0.03, against entry 159's (0.003 and 0.01). Rule 1: a unit that keeps 0.01 in both has the same
RMSEs. Rule 2: how many keep 0.03; per unit the new reference over entry 159's; `cover_informative` at 120 s
(entry 158) against both. Rule 3: the grid's edge flatters the ratios if the new references' force interval
lies below 0.98. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry161/analyse.py
"""

from pathlib import Path

from anytip.report.cross_sensor import mean_interval, paired_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
GPU = HERE.parent
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
FOLDS, ACROSS = (0, 1), "response@cover_informative"


def references(entry: str) -> dict[str, dict]:
    """unit -> its reference row, folds 0 and 1 of `entry`."""
    out = {}
    for k in FOLDS:
        got = read_json(GPU / entry / f"other16f_seed{k}" / "references.json")
        out.update({r["unit"]: r for r in got["rows"]})
    return out


def plan_rows() -> list[dict]:
    """Entry 158's `cover_informative` rows at 120 s, folds 0 and 1, with their fold's seed."""
    out = []
    for k in FOLDS:
        run = read_json(GPU / "entry158" / f"other16f_seed{k}" / "rows.json")
        out += [{**r, "seed": run["seed"]} for r in run["rows"]
                if r["method"] == ACROSS and r["budget_s"] == 120.0]
    return out


def main() -> None:
    new, old = references("entry161"), references("entry159")
    both = [u for u in new if new[u]["reference_lr"] == old[u]["reference_lr"] == 0.01]
    same = all(new[u][k] == old[u][k] for u in both for k in KEYS.values())
    print(f"rule 1: {len(both)} units keep 0.01 in both; their RMSEs {'equal' if same else 'DIFFER'}")
    kept = sum(r["reference_lr"] == 0.03 for r in new.values())
    print(f"\nrule 2: {kept} of {len(new)} units keep 0.03")
    units = sorted(new)
    for name, key in KEYS.items():
        print(f"new reference over entry 159's, per unit, {name}: "
              f"x{paired_text([new[u][key] / old[u][key] for u in units])}")
    text = "{:.3f}x [{:.2f}, {:.2f}]".format
    for label, refs in (("entry 159's references", old), ("with 0.03 tried", new)):
        rows = plan_rows() + [{**r, "method": "per_unit"} for r in refs.values()]
        cells = [text(*mean_interval(list(unit_ratios(rows, key)[ACROSS, 120.0].values())))
                 for key in KEYS.values()]
        print(f"`cover_informative` at 120 s against {label}: " + " / ".join(cells))
    _, lower, upper = paired_interval([new[u]["force_rmse_n"] / old[u]["force_rmse_n"] for u in units])
    verdict = ("the grid's edge flatters the ratios" if upper < 0.98 else
               "the grid stands" if lower >= 0.98 else "undecided")
    print(f"\nrule 3: {verdict}")


if __name__ == "__main__":
    main()
