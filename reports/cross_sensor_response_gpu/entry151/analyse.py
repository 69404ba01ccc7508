"""Research log entry 151's reading: other16's designed plan at 120 s with each press chosen for what it
tells the codes (fold K's informative design of plan150), paired per unit with entry 146's design.
Rule 1 (gate): the references' rows equal entry 146's, every designed plan within 120 s (seconds and
presses beside entry 146's). Rule 2: the validation units' mean loss over draws and folds, each designed
method, against entry 146's. Rule 3: informative over entry 146 per unit, force and angle, each unit's
draws averaged. Reads the draws whose four folds ran. Then the amendment's fleet88 step (its gate, its
validation units' rule and the 88 held-out units). From the repository root:

    python reports/cross_sensor_response_gpu/entry151/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import paired_interval, paired_text
from anytip.rundir import read_json

HERE = Path(__file__).parent
E121 = runpy.run_path(str(HERE.parent / "entry121" / "analyse.py"))  # run_dir, rows, record, unit_figure
E123 = runpy.run_path(str(HERE.parent / "entry123" / "analyse.py"))  # off_over_on
FOLDS = E121["FOLDS"]
BASE = HERE.parent / "entry146" / "at120"
NEW = HERE / "at120"
DESIGNED = ("response@designed", "response+use@designed")


def draws_done(new: Path = NEW) -> list[int]:
    return [
        d for d in (0, 1, 2) if all((E121["run_dir"](new, d, k) / "metrics.json").is_file() for k in FOLDS)
    ]


def plans(d: int, k: int, root: Path) -> np.ndarray:
    """(n, 2) every designed row's robot seconds and presses."""
    return np.array(
        [
            (r["calib_seconds"], r["presses"])
            for r in E121["rows"](root, d, k)
            if r["method"] in DESIGNED and r["budget_s"] == 120
        ]
    )


def references(rows: list[dict]) -> list[tuple]:
    """The per-unit references' rows, comparable between runs."""
    return sorted(tuple(sorted(r.items())) for r in rows if r["method"] == "per_unit")


def ratios_of(a: dict, b: dict) -> list[float]:
    """Per key of b (a validation unit-fold), its loss in a over its loss in b."""
    return [a[key] / b[key] for key in sorted(b)]


def gate(d: int, k: int, new: Path = NEW) -> bool:
    equal = references(E121["rows"](new, d, k)) == references(E121["rows"](BASE, d, k))
    mine, theirs = plans(d, k, new), plans(d, k, BASE)
    print(
        f"rule 1, draw {d}, fold {k}: references {'equal' if equal else 'DIFFER'}; designed plans at most "
        f"{mine[:, 0].max():.1f} s, {mine[:, 0].mean():.1f} s and {mine[:, 1].mean():.1f} presses a unit "
        f"(entry 146: {theirs[:, 0].mean():.1f} s, {theirs[:, 1].mean():.1f})"
    )
    return equal and mine[:, 0].max() <= 120.0 + 1e-9


def unit_losses(root: Path, draws: list[int], method: str) -> dict[tuple[int, str], float]:
    """Each validation unit-fold's loss of `method` at 120 s, its draws averaged."""
    got: dict[tuple[int, str], list[float]] = {}
    for d in draws:
        for k in FOLDS:
            for u, v in E121["record"](root, d, k)["val_loss_units"][method]["120"].items():
                got.setdefault((k, u), []).append(v)
    return {key: float(np.mean(v)) for key, v in got.items()}


def validation(draws: list[int], new_root: Path = NEW) -> tuple[dict[str, float], float]:
    """Per designed method: the validation units' mean loss over the draws and folds, new over entry 146's;
    beside it, the paired view: each unit-fold's ratio, and their geometric mean's interval; returns the
    changes and the upper bound of `response@designed`'s paired interval."""
    change, upper = {}, 1.0
    for m in DESIGNED:
        new, old = (
            np.mean([E121["record"](root, d, k)["val_loss"][m]["120"] for d in draws for k in FOLDS])
            for root in (new_root, BASE)
        )
        change[m] = new / old - 1
        print(
            f"rule 2, {m}: validation mean {new:.5f} against entry 146's {old:.5f} ({100 * change[m]:+.1f}%)"
        )
        a, b = unit_losses(new_root, draws, m), unit_losses(BASE, draws, m)
        ratios = ratios_of(a, b)
        upper = paired_interval(ratios)[2] if m == DESIGNED[0] else upper
        cells = ", ".join(f"fold {k} {u} x{a[(k, u)] / b[(k, u)]:.3f}" for k, u in sorted(b))
        print(f"  paired per unit-fold: x{paired_text(ratios)}; {cells}")
    return change, upper


def fleet88(k: int, root: Path) -> Path:
    return root / f"fleet88_seed{k}"


def fleet88_record(k: int, root: Path) -> dict:
    return read_json(fleet88(k, root) / "provenance.json")["cross_sensor"][f"seed{k}"]


def fleet88_reading() -> None:
    """The amendment's fleet88 step: gate, the validation units' rule, then the 88 held-out units."""
    if not all((fleet88(k, NEW) / "metrics.json").is_file() for k in (0, 1)):
        print("fleet88: not run yet")
        return
    results = {
        (k, root): read_json(fleet88(k, root) / "metrics.json")["results"]
        for k in (0, 1)
        for root in (NEW, BASE)
    }
    ok = True
    for k in (0, 1):
        new, old = results[(k, NEW)], results[(k, BASE)]
        refs = [references(new), references(old)]
        longest = max(r["calib_seconds"] for r in new if r["method"] in DESIGNED)
        ok &= refs[0] == refs[1] and longest <= 120.0 + 1e-9
        print(
            f"fleet88 rule 1, fold {k}: references {'equal' if refs[0] == refs[1] else 'DIFFER'}; "
            "designed plans "
            f"at most {longest:.1f} s"
        )
    print(f"fleet88 rule 1: {'holds' if ok else 'FAILS'}")
    change, paired_hi = {}, 1.0
    for m in DESIGNED:
        a, b = (
            {(k, u): v for k in (0, 1) for u, v in fleet88_record(k, r)["val_loss_units"][m]["120"].items()}
            for r in (NEW, BASE)
        )
        change[m] = float(np.mean(list(a.values())) / np.mean(list(b.values())) - 1)
        ratios = ratios_of(a, b)
        if m == "response@designed":
            paired_hi = paired_interval(ratios)[2]
        print(
            f"fleet88 validation, {m}: mean {np.mean(list(a.values())):.5f} "
            f"against {np.mean(list(b.values())):.5f} "
            f"({100 * change[m]:+.1f}%); paired x{paired_text(ratios)}"
        )
    taken = change["response@designed"] <= -0.03 and change["response+use@designed"] <= 0 and paired_hi < 1
    print(f"fleet88 rule: {'taken' if taken else 'not taken'}")
    got_new, got_old = ([r for k in (0, 1) for r in results[(k, root)]] for root in (NEW, BASE))
    for m in DESIGNED:
        per = {"new": E121["at_120"](got_new, m), "base": E121["at_120"](got_old, m)}
        print(f"  fleet88 held out, {m}: {E123['off_over_on'](per['new'], per['base'], 'informative')}")


def held_out(draws: list[int], new: Path, label: str) -> tuple[float, float]:
    """Rule 3's figures, the new design over entry 146's per unit for each designed method; returns the
    interval of `response@designed`'s force ratio."""
    bounds = (0.0, 0.0)
    for m in DESIGNED:
        per = {arm: E121["unit_figure"](root, draws, m) for arm, root in (("new", new), ("base", BASE))}
        print(f"  {m}: {E123['off_over_on'](per['new'], per['base'], label)}")
        if m == DESIGNED[0]:
            ratios = [per["new"]["force"][u] / per["base"]["force"][u] for u in per["base"]["force"]]
            bounds = paired_interval(ratios)[1:]
    return bounds


def main() -> None:
    draws = draws_done()
    print(f"draws with all four folds: {draws}")
    ok = all(gate(d, k) for d in draws for k in FOLDS)
    print(f"rule 1: {'holds' if ok else 'FAILS'}")
    change, _ = validation(draws)
    worth = change["response@designed"] <= -0.03 and change["response+use@designed"] <= 0
    print(f"rule 2: {'worth building and scoring on fleet88' if worth else 'not taken'}")
    print("rule 3, informative over entry 146's design, per unit, draws averaged:")
    lo, hi = held_out(draws, NEW, "informative")
    print(
        "  reading (force, the plan alone): "
        + ("I" if hi <= 0.98 else "W" if lo >= 0.98 and hi <= 1.02 else "partly")
    )
    fleet88_reading()


if __name__ == "__main__":
    main()
