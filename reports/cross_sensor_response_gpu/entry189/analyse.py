"""Research log entry 189's reading: the gate (the control's rows against entry 130's draw 0 fold 0; every
rescoring's references and plan-alone rows against entries 130 and 131), the choice on validation units (rule
2) and the held-out units per unit (rule 3). Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry189/analyse.py > \\
        reports/cross_sensor_response_gpu/entry189/logs/analyse.log
"""

import runpy
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats

HERE = Path(__file__).parent
GPU = HERE.parent
OTHER16 = runpy.run_path(str(GPU / "entry121" / "analyse.py"))
FLEET88 = runpy.run_path(str(GPU / "entry122" / "analyse.py"))
PAIRING = runpy.run_path(str(GPU / "entry123" / "analyse.py"))
ON = {"other16": GPU / "entry130", "fleet88": GPU / "entry131"}  # today's recipe, use_weight 1
ARM = HERE / "w4"
ALONE = ("response@designed", "response@cover_informative")
WITH_USE = ("response+use@designed", "response+use@cover_informative")


def data_check(new: list[dict[str, Any]], old: list[dict[str, Any]], shared: tuple[str, ...]
               ) -> tuple[bool, int, float]:
    """Entry 121's `data_check` with each plan's robot seconds left out of its identity (rule 1 as amended):
    the designed plan's seconds count its presses' recorded leads since commit 86f53d6b, after entries
    130-131, where they counted 2 s a move; its rows are the same. Prints how far the seconds moved."""
    def plans(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
        mine = [r for r in rows if r["method"] in shared]
        return sorted(mine, key=lambda r: (r["method"], r["unit"], r["seed"]))

    pairs = zip(plans(new), plans(old), strict=True)
    moved = max(abs(a["calib_seconds"] - b["calib_seconds"]) for a, b in pairs)
    print(f"  the plans' robot seconds move by up to {moved:.3f} s")
    unpriced = ([{**r, "calib_seconds": None} for r in rows] for rows in (new, old))
    return OTHER16["data_check"](*unpriced, shared)


def gate() -> bool:
    """Rule 1: the control equals entry 130 in every row; each rescoring's references and plans alone
    equal (rule 1 as amended: `data_check`)."""
    control = data_check(OTHER16["rows"](HERE / "w1", 0, 0), OTHER16["rows"](ON["other16"], 0, 0),
                         ALONE + WITH_USE)
    print(f"rule 1, control (other16 fold 0, use_weight 1): rows {'equal' if control[0] else 'DIFFER'}, its "
          f"{control[1]} RMSEs move by up to {control[2]:.2g}")
    ok = control[0] and control[2] == 0.0
    checks = [(f"other16 fold {k}", OTHER16["rows"](ARM, 0, k), OTHER16["rows"](ON["other16"], 0, k))
              for k in OTHER16["FOLDS"]]
    checks += [(f"fleet88 fold {k}", FLEET88["rows"](ARM, k), FLEET88["rows"](ON["fleet88"], k))
               for k in FLEET88["FOLDS"]]
    for name, new, old in checks:
        equal, n, moved = data_check(new, old, ALONE)
        print(f"rule 1, {name}: references and plans {'equal' if equal else 'DIFFER'}, the plans alone's {n} "
              f"RMSEs move by up to {moved:.2g}")
        ok &= equal and moved == 0.0
    return ok


def losses(method: str) -> dict[str, dict[tuple[str, int, str], float]]:
    """Each validation unit-fold's loss of `method` at 120 s, weight 4 and today's (other16 in draw 0)."""
    out: dict[str, dict[tuple[str, int, str], float]] = {"w4": {}, "w1": {}}
    for arm, roots in (("w4", {"other16": ARM, "fleet88": ARM}), ("w1", ON)):
        for k in OTHER16["FOLDS"]:
            got = OTHER16["record"](roots["other16"], 0, k)["val_loss_units"][method]["120"]
            out[arm] |= {("other16", k, u): v for u, v in got.items()}
        for k in FLEET88["FOLDS"]:
            got = FLEET88["record"](roots["fleet88"], k)["val_loss_units"][method]["120"]
            out[arm] |= {("fleet88", k, u): v for u, v in got.items()}
    return out


def choice() -> bool:
    """Rule 2 (a) and (b)."""
    taken = True
    for method in WITH_USE:
        got = losses(method)
        fleet = [key for key in got["w1"] if key[0] == "fleet88"]
        m4, m1 = (np.mean([got[a][key] for key in fleet]) for a in ("w4", "w1"))
        logs = [float(np.log(got["w4"][key] / got["w1"][key])) for key in got["w1"]]
        mean, sem = float(np.mean(logs)), float(stats.sem(logs))
        lo, hi = stats.t.interval(0.95, len(logs) - 1, loc=mean, scale=sem)
        print(f"rule 2, {method}: (a) fleet88's {len(fleet)} validation units {m4:.5f} against {m1:.5f} "
              f"({100 * (m4 / m1 - 1):+.2f}%); (b) {len(logs)} validation unit-folds, mean log(4 / 1) "
              f"{mean:+.4f} [{lo:+.4f}, {hi:+.4f}] "
              f"(x{np.exp(mean):.3f} [{np.exp(lo):.3f}, {np.exp(hi):.3f}])")
        if method == "response+use@designed":
            taken &= bool(m4 < 0.99 * m1 and hi < 0)
        else:
            taken &= bool(m4 <= m1 and mean <= 0)
    print(f"the choice: {'taken' if taken else 'not taken'}")
    return taken


def held_out() -> None:
    """Rule 3: the held-out units, weight 4 over today's per unit, every method."""
    def other16(root: Path, method: str) -> dict[str, dict[str, float]]:
        return OTHER16["unit_figure"](root, [0], method)

    for name, figure, on in (("other16 (draw 0)", other16, ON["other16"]),
                             ("fleet88", FLEET88["unit_figure"], ON["fleet88"])):
        print(f"rule 3, {name}'s held-out units, 120 s, use_weight 4 over 1 per unit:")
        for m in WITH_USE:
            print(f"  {m}: {PAIRING['off_over_on'](figure(ARM, m), figure(on, m), 'w4')}")


if __name__ == "__main__":
    if gate():
        choice()
        held_out()
    else:
        print("gate failed: no row with ordinary use is read")
