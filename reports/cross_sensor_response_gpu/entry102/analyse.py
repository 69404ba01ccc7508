"""Research log entry 102's reading: the designed plan with and without the plan's residual correction on
fleet88's CPU models, `cover_informative` beside it in the same runs. Rule 1 (each arm's
`cover_informative` rows equal entry 101's or entry 99's), the validation units' mean loss per plan and
arm, the held-out ratios per plan and arm with the per-unit factor of the correction, and rule 3's ratio
of that factor on the designed plan over that on `cover_informative`. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry102/analyse.py
"""

from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
ARMS = {"on": HERE.parent / "entry101" / "fleet88_cpu", "off": HERE.parent / "entry99" / "fleet88_cpu"}
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
PLANS = ("cover_informative", "designed")
FOLDS = (0, 1)


def run_dir(arm: str, k: int) -> Path:
    return HERE / f"fleet88_cpu_{arm}" / f"fleet88_seed{k}"


def record(root: Path, k: int) -> dict[str, Any]:
    return read_json(root / "provenance.json")["cross_sensor"][f"seed{k}"]


def rows(roots: list[Path]) -> list[dict[str, Any]]:
    return [r for root in roots for r in read_json(root / "metrics.json")["results"]]


def same_as_before(arm: str) -> None:
    """Rule 1: the arm's `cover_informative` rows against the run it must reproduce."""
    method = "response@cover_informative"
    for k in FOLDS:
        new, old = run_dir(arm, k), ARMS[arm] / f"fleet88_seed{k}"
        losses = [record(r, k)["val_loss_units"][method]["120"] for r in (new, old)]
        held = [sorted((r["unit"], r["seed"], r[key]) for r in rows([root]) for key in KEYS.values()
                       if r["method"] in (method, "per_unit")) for root in (new, old)]
        same = losses[0] == losses[1] and held[0] == held[1]
        where = old.relative_to(HERE.parent)
        print(f"rule 1, arm {arm}, fold {k}: {method} rows {'equal' if same else 'DIFFER from'} {where}")


def validation(method: str) -> None:
    means = {arm: np.mean([record(run_dir(arm, k), k)["val_loss"][method]["120"] for k in FOLDS])
             for arm in ARMS}
    per = [record(run_dir("on", k), k)["val_loss_units"][method]["120"][u]
           / record(run_dir("off", k), k)["val_loss_units"][method]["120"][u]
           for k in FOLDS for u in record(run_dir("on", k), k)["val_loss_units"][method]["120"]]
    change = 100 * (means["on"] / means["off"] - 1)
    print(f"  validation: on {means['on']:.5f}, off {means['off']:.5f} ({change:+.2f}%);"
          f" per unit x{paired_text(per)}, {sum(r < 1 for r in per)} of {len(per)} lower")


def per_unit(arm: str, key: str) -> dict[str, dict[str, float]]:
    got = unit_ratios(rows([run_dir(arm, k) for k in FOLDS]), key)
    return {plan: got[(f"response@{plan}", 120.0)] for plan in PLANS}


def main() -> None:
    for arm in ARMS:
        same_as_before(arm)
    for plan in PLANS:
        print(f"response@{plan}, 120 s alone")
        validation(f"response@{plan}")
        for label, key in KEYS.items():
            on, off = per_unit("on", key)[plan], per_unit("off", key)[plan]
            (m, lo, hi), (c, clo, chi) = (mean_interval(list(p.values())) for p in (on, off))
            factor = paired_text([on[u] / off[u] for u in off])
            print(f"  held out {label}: on {m:.3f}x [{lo:.2f}, {hi:.2f}], off {c:.3f}x [{clo:.2f}, {chi:.2f}]"
                  f"; correction per unit x{factor} over {len(off)} units")
    for label, key in KEYS.items():
        on, off = per_unit("on", key), per_unit("off", key)
        units = list(off["designed"])
        gain = {plan: [on[plan][u] / off[plan][u] for u in units] for plan in PLANS}
        rel = [d / c for d, c in zip(gain["designed"], gain["cover_informative"], strict=True)]
        print(f"rule 3, {label}: the correction's factor on designed over that on cover_informative "
              f"x{paired_text(rel)} over {len(units)} units")
        apart = {a: paired_text([got["designed"][u] / got["cover_informative"][u] for u in units])
                 for a, got in (("on", on), ("off", off))}
        print(f"  designed over cover_informative, arm on: x{apart['on']}; arm off: x{apart['off']}")


if __name__ == "__main__":
    main()
