"""Research log entry 154's reading: the designed plan at 30 and 60 s on fleet88 and other16.
Rule 1: each run's references equal its base run's, every plan within its budget and on one orientation.
Rule 2: the designed plan's curve (120 and 600 s from entry 146), alone and with ordinary use, each unit's
draws averaged. Rule 3: the designed plan over entry 153's `cover_informative` per unit, at 30 and 60 s
against 120 s. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry154/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import paired_text, unit_ratios

HERE = Path(__file__).parent
GPU = HERE.parent
E153 = runpy.run_path(str(GPU / "entry153" / "analyse.py"))
metrics, f88, o16, checked, curve = (E153[n] for n in ("metrics", "f88", "o16", "checked", "curve"))
KEYS, Rows = E153["KEYS"], E153["Rows"]
E146 = GPU / "entry146"
DESIGNED, DESIGNED_USE = "response@designed", "response+use@designed"
INFORMED = {DESIGNED: E153["ALONE"], DESIGNED_USE: E153["USE"]}
BUDGETS = (30.0, 60.0)


def gate(name: str, run: Path, base: Path) -> None:
    """Rule 1 for one run."""
    got = metrics(run)
    mine = [r for r in got if r["method"] in INFORMED]
    orientations = sorted({r["orientations"] for r in mine})
    presses = {b: sorted({r["presses"] for r in mine if r["budget_s"] == b}) for b in BUDGETS}
    seconds = {b: [r["calib_seconds"] for r in mine if r["budget_s"] == b] for b in BUDGETS}
    print(f"rule 1, {name}: {checked(run, base, tuple(INFORMED))}; "
          f"orientations per plan {orientations}; presses "
          + ", ".join(f"{b:g} s {p}" for b, p in presses.items()) + "; robot seconds "
          + ", ".join(f"{b:g} s mean {np.mean(v):.1f} ({min(v):.1f}-{max(v):.1f})"
                      for b, v in seconds.items()))


def gaps(designed: Rows, informed: Rows, key: str) -> dict[tuple[str, float], dict[str, float]]:
    """(designed method, budget) -> {unit: the designed plan's ratio over `cover_informative`'s}."""
    a, b = unit_ratios(designed, key), unit_ratios(informed, key)
    return {(m, bud): {u: a[(m, bud)][u] / b[(INFORMED[m], bud)][u] for u in a[(m, bud)]}
            for (m, bud) in a if m in INFORMED and (INFORMED[m], bud) in b}


def rule3(name: str, designed: Rows, informed: Rows) -> None:
    """The gap per unit at each budget, and at 30 and 60 s over the gap at 120 s."""
    for label, key in KEYS.items():
        g = gaps(designed, informed, key)
        print(f"rule 3, {name}, {label}: designed over cover_informative per unit")
        for m in INFORMED:
            print("  " + m + ": " + ", ".join(f"{b:g} s x{paired_text(list(g[(m, b)].values()))}"
                                             for b in (*BUDGETS, 120.0) if (m, b) in g))
            for b in BUDGETS:
                print(f"    gap({b:g}) / gap(120) = x"
                      + paired_text([g[(m, b)][u] / g[(m, 120.0)][u] for u in g[(m, b)]]))


def table(name: str, designed: Rows) -> None:
    """Rule 2: the designed plan's curve, force / angle."""
    c = curve(designed, tuple(INFORMED), (*BUDGETS, 120.0, 600.0))
    print(f"rule 2, {name}: the designed plan, force / angle, mean over units [95%]")
    print("| robot-s | alone | with ordinary use |\n|---|---|---|")
    for b in (*BUDGETS, 120.0, 600.0):
        print(f"| {b:g} | {c.get((DESIGNED, b), '')} | {c.get((DESIGNED_USE, b), '')} |")


def main() -> None:
    start = GPU.parent / "cross_sensor_response_start"
    folds, o16_folds = E153["F88_FOLDS"], E153["O16_FOLDS"]
    for k in folds:
        gate(f"fleet88 fold {k}", f88(HERE, k), f88(start, k))
    draws = [d for d in E153["DRAWS"] if all((o16(HERE, d, k) / "metrics.json").is_file() for k in o16_folds)]
    for d in draws:
        for k in o16_folds:
            gate(f"other16 draw {d} fold {k}", o16(HERE, d, k), start / f"other16_seed{k}")
    f88_designed = [r for k in folds for root in (HERE, E146 / "at120", E146 / "at600")
                    for r in metrics(f88(root, k))]
    f88_informed = [r for k in folds for r in metrics(f88(GPU / "entry153", k))]
    table("fleet88 (88 units)", f88_designed)
    rule3("fleet88", f88_designed, f88_informed)
    if not draws:
        return
    o16_designed = [r for d in draws for k in o16_folds for root in (HERE, E146 / "at120", E146 / "at600")
                    for r in metrics(o16(root, d, k))]
    o16_informed = [r for d in draws for k in o16_folds for r in metrics(o16(GPU / "entry153", d, k))]
    table(f"other16 (16 units, draws {', '.join(map(str, draws))} averaged)", o16_designed)
    rule3("other16", o16_designed, o16_informed)


if __name__ == "__main__":
    main()
