"""Research log entry 151's reading: other16's designed plan at 120 s with each press chosen for what it tells
the codes (fold K's informative design of plan150), paired per unit with entry 146's design. Rule 1 (gate): the
references' rows equal entry 146's, every designed plan within 120 s (seconds and presses beside entry 146's).
Rule 2: the validation units' mean loss over draws and folds, each designed method, against entry 146's. Rule 3:
informative over entry 146 per unit, force and angle, each unit's draws averaged. Reads the draws whose four folds
ran. From the repository root:

    python reports/cross_sensor_response_gpu/entry151/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import paired_interval

HERE = Path(__file__).parent
E121 = runpy.run_path(str(HERE.parent / "entry121" / "analyse.py"))  # run_dir, rows, record, unit_figure
E123 = runpy.run_path(str(HERE.parent / "entry123" / "analyse.py"))  # off_over_on
FOLDS = E121["FOLDS"]
BASE = HERE.parent / "entry146" / "at120"
NEW = HERE / "at120"
DESIGNED = ("response@designed", "response+use@designed")


def draws_done() -> list[int]:
    return [d for d in (0, 1, 2) if all((E121["run_dir"](NEW, d, k) / "metrics.json").is_file() for k in FOLDS)]


def plans(d: int, k: int, root: Path) -> np.ndarray:
    """(n, 2) every designed row's robot seconds and presses."""
    return np.array([(r["calib_seconds"], r["presses"]) for r in E121["rows"](root, d, k)
                     if r["method"] in DESIGNED and r["budget_s"] == 120])


def gate(d: int, k: int) -> bool:
    def references(root: Path) -> list[tuple]:
        return sorted(tuple(sorted(r.items())) for r in E121["rows"](root, d, k) if r["method"] == "per_unit")

    equal = references(NEW) == references(BASE)
    mine, theirs = plans(d, k, NEW), plans(d, k, BASE)
    print(f"rule 1, draw {d}, fold {k}: references {'equal' if equal else 'DIFFER'}; designed plans at most "
          f"{mine[:, 0].max():.1f} s, {mine[:, 0].mean():.1f} s and {mine[:, 1].mean():.1f} presses a unit "
          f"(entry 146: {theirs[:, 0].mean():.1f} s, {theirs[:, 1].mean():.1f})")
    return equal and mine[:, 0].max() <= 120.0 + 1e-9


def validation(draws: list[int]) -> dict[str, float]:
    """Per designed method: the validation units' mean loss over the draws and folds, new over entry 146's."""
    change = {}
    for m in DESIGNED:
        new, old = (np.mean([E121["record"](root, d, k)["val_loss"][m]["120"] for d in draws for k in FOLDS])
                    for root in (NEW, BASE))
        change[m] = new / old - 1
        print(f"rule 2, {m}: validation mean {new:.5f} against entry 146's {old:.5f} ({100 * change[m]:+.1f}%)")
    return change


def main() -> None:
    draws = draws_done()
    print(f"draws with all four folds: {draws}")
    ok = all(gate(d, k) for d in draws for k in FOLDS)
    print(f"rule 1: {'holds' if ok else 'FAILS'}")
    change = validation(draws)
    worth = change["response@designed"] <= -0.03 and change["response+use@designed"] <= 0
    print(f"rule 2: {'worth building and scoring on fleet88' if worth else 'not taken'}")
    print("rule 3, informative over entry 146's design, per unit, draws averaged:")
    for m in DESIGNED:
        per = {arm: E121["unit_figure"](root, draws, m) for arm, root in (("new", NEW), ("base", BASE))}
        print(f"  {m}: {E123['off_over_on'](per['new'], per['base'], 'informative')}")
        if m == "response@designed":
            ratios = [per["new"]["force"][u] / per["base"]["force"][u] for u in per["base"]["force"]]
            _, lo, hi = paired_interval(ratios)
            reading = "I" if hi <= 0.98 else "W" if lo >= 0.98 and hi <= 1.02 else "partly"
            print(f"  reading (force, the plan alone): {reading}")


if __name__ == "__main__":
    main()
