"""Research log entry 144's reading: other16 at 600 s with today's recipe over three start draws, draw 0
being entry 142's runs. Rule 1: each draw's references' rows and designed plans equal entry 142's. Rule 2:
both plans at 600 s, alone and with ordinary use, each unit's draws averaged first. Rule 3: each draw's own
means, and designed over `cover_informative` per unit. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry144/analyse.py
"""

import importlib.util
from pathlib import Path
from typing import Any

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios

HERE = Path(__file__).parent
_spec = importlib.util.spec_from_file_location("entry121_analyse", HERE.parent / "entry121" / "analyse.py")
e121 = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(e121)
DRAW0 = HERE.parent / "entry142"
FOLDS, KEYS, METHODS = e121.FOLDS, e121.KEYS, e121.METHODS
BUDGET = 600.0


def root_of(d: int) -> Path:
    return DRAW0 if d == 0 else HERE


def draw_rows(draws: list[int]) -> list[dict[str, Any]]:
    return [r for d in draws for k in FOLDS for r in e121.rows(root_of(d), d, k)]


def per_unit(got: list[dict[str, Any]], method: str) -> dict[str, dict[str, float]]:
    """Per output kind, per unit: the method's ratio at 600 s, the unit's draws averaged."""
    return {label: unit_ratios(got, key)[(method, BUDGET)] for label, key in KEYS.items()}


def main() -> None:
    draws = [0] + [d for d in (1, 2)
                   if all((e121.run_dir(HERE, d, k) / "metrics.json").is_file() for k in FOLDS)]
    for d in draws[1:]:
        for k in FOLDS:
            equal, n, drift = e121.data_check(e121.rows(HERE, d, k), e121.rows(DRAW0, 0, k),
                                              ("response@designed",))
            print(f"rule 1, draw {d}, fold {k}: references and designed plans "
                  f"{'equal' if equal else 'DIFFER'} to draw 0's; its {n} designed RMSEs differ from "
                  f"draw 0's by up to {drift:.3f} relative")
    per = {m: per_unit(draw_rows(draws), m) for m in METHODS}
    print(f"rule 2, draws {draws} averaged per unit, 600 s:")
    for m in METHODS:
        print(f"  {m}: {e121.line(per[m])}")
    print("rule 3, each draw alone, force mean:")
    for m in METHODS:
        means = [mean_interval(list(per_unit(draw_rows([d]), m)["force"].values()))[0] for d in draws]
        print(f"  {m}: " + ", ".join(f"draw {d} {v:.3f}x" for d, v in zip(draws, means, strict=True)))
    print("rule 3, designed over cover_informative, paired per unit:")
    for use in ("response+use", "response"):
        a, b = per[f"{use}@designed"], per[f"{use}@cover_informative"]
        paired = {label: paired_text([a[label][u] / b[label][u] for u in b[label]]) for label in KEYS}
        print(f"  {use}: " + ", ".join(f"{label} x{text}" for label, text in paired.items()))


if __name__ == "__main__":
    main()
