"""Research log entry 137's reading: fleet88's rescoring with the response model trained again, at a code
of 32 (`code32`) and at 16 with another training draw (`draw1`), paired per unit with entry 131's run of
today's recipe on the folds every arm ran. The gate (references and designed plans equal entry 131's,
`cover_informative`'s plans within 120 s), then each arm over entry 131 and `code32` over `draw1` per method,
force and angle, the validation units' losses, and the reading written down. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry137/analyse.py
"""

import runpy
from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_interval, paired_text

HERE = Path(__file__).parent
GPU = HERE.parent
FLEET88 = runpy.run_path(str(GPU / "entry122" / "analyse.py"))  # its rows, record, METHODS
READING = runpy.run_path(str(GPU / "entry121" / "analyse.py"))  # data_check, at_120, KEYS
ARMS = {"code32": HERE / "code32", "draw1": HERE / "draw1", "entry 131": GPU / "entry131"}
DESIGNED = ("response@designed", "response+use@designed")
RECIPE = "entry 131"


def folds(arms: tuple[str, ...] = tuple(ARMS)) -> list[int]:
    """The folds every arm of `arms` ran in full."""
    return [k for k in FLEET88["FOLDS"]
            if all((ARMS[a] / f"fleet88_seed{k}" / "metrics.json").is_file() for a in arms)]


def gate(ks: list[int], arms: tuple[str, ...] = ("code32", "draw1")) -> bool:
    """References and designed plans equal entry 131's; `cover_informative`'s plans within 120 s."""
    ok = True
    for arm in arms:
        for k in ks:
            new = FLEET88["rows"](ARMS[arm], k)
            equal, _, _ = READING["data_check"](new, FLEET88["rows"](ARMS[RECIPE], k), DESIGNED)
            longest = max(r["calib_seconds"] for r in new if r["method"].endswith("@cover_informative"))
            ok &= equal and longest <= 120.0
            print(f"gate, {arm}, fold {k}: references and designed plans {'equal' if equal else 'DIFFER'}; "
                  f"cover_informative's longest plan {longest:.1f} s")
    return ok


def per_unit(arm: str, method: str, ks: list[int]) -> dict[str, dict[str, float]]:
    """Per output kind, per unit: the arm's ratio at 120 s on folds ks."""
    return READING["at_120"]([r for k in ks for r in FLEET88["rows"](ARMS[arm], k)], method)


def paired(a: dict[str, float], b: dict[str, float]) -> tuple[str, float, float]:
    """a over b per unit: its text, and the bounds of the geometric mean's interval."""
    ratios = [a[u] / b[u] for u in b]
    _, lo, hi = paired_interval(ratios)
    return paired_text(ratios), lo, hi


def validation_mean(arm: str, method: str, ks: list[int]) -> float:
    """The arm's validation units' mean loss of `method` at 120 s over folds ks."""
    return float(np.mean([v for k in ks for v in
                          FLEET88["record"](ARMS[arm], k)["val_loss_units"][method]["120"].values()]))


def validation(ks: list[int]) -> None:
    """Each arm's validation units' mean loss per method at 120 s."""
    print("validation units, mean loss at 120 s:")
    for m in FLEET88["METHODS"]:
        print(f"  {m}: " + ", ".join(f"{arm} {validation_mean(arm, m, ks):.5f}" for arm in ARMS))


def verdict(force: dict[str, dict[str, dict[str, float]]]) -> str:
    """The reading written down, on `response@designed`'s force."""
    _, lo_recipe, hi_recipe = paired(force["code32"], force[RECIPE])
    _, lo_draw, hi_draw = paired(force["code32"], force["draw1"])
    if hi_recipe < 0.97 and hi_draw < 1.0:
        return "W"
    if lo_draw <= 1.0 <= hi_draw and lo_recipe >= 0.97 and hi_recipe <= 1.03:
        return "not W"
    return "partly"


def main() -> None:
    ks = folds()
    print(f"folds every arm ran: {ks}")
    if not ks or not gate(ks):
        print("gate failed or nothing ran: nothing is read")
        return
    got: dict[str, Any] = {}
    for m in FLEET88["METHODS"]:
        per = {arm: per_unit(arm, m, ks) for arm in ARMS}
        got[m] = per
        print(f"{m}, 120 s, over {len(per[RECIPE]['force'])} held-out units:")
        for kind in READING["KEYS"]:
            means = {arm: mean_interval(list(per[arm][kind].values())) for arm in ARMS}
            print(f"  {kind}: " + ", ".join(f"{arm} {v[0]:.3f}x [{v[1]:.2f}, {v[2]:.2f}]"
                                            for arm, v in means.items()))
            for a, b in (("code32", RECIPE), ("draw1", RECIPE), ("code32", "draw1")):
                print(f"    {a} over {b}: x{paired(per[a][kind], per[b][kind])[0]}")
    validation(ks)
    force = {arm: got["response@designed"][arm]["force"] for arm in ARMS}
    print(f"the reading, response@designed, force: {verdict(force)}")
    wider()


def wider() -> None:
    """Beside the reading (the amendment): `code32` over entry 131 on every fold both ran, and per fold."""
    ks = folds(("code32", RECIPE))
    if len(ks) < 2 or not gate(ks[1:], ("code32",)):
        return
    print(f"beside it, code32 over entry 131 per unit, folds {ks}:")
    for m in FLEET88["METHODS"]:
        for kind in READING["KEYS"]:
            mine = per_unit("code32", m, ks)[kind]
            mean, lo, hi = mean_interval(list(mine.values()))
            cells = [f"folds {ks} x{paired(mine, per_unit(RECIPE, m, ks)[kind])[0]} "
                     f"({mean:.3f}x [{lo:.2f}, {hi:.2f}])"]
            for k in ks:
                mine, theirs = per_unit("code32", m, [k])[kind], per_unit(RECIPE, m, [k])[kind]
                cells.append(f"fold {k} x{paired(mine, theirs)[0]} "
                             f"({mean_interval(list(mine.values()))[0]:.3f}x)")
            print(f"  {m}, {kind}: " + "; ".join(cells))
    for k in ks:
        print(f"  fold {k}'s validation units, code32 / entry 131: " + ", ".join(
            f"{m} {validation_mean('code32', m, [k]):.5f} / {validation_mean(RECIPE, m, [k]):.5f}"
            for m in FLEET88["METHODS"]))


if __name__ == "__main__":
    main()
