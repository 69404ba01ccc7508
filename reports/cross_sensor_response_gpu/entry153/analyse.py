"""Research log entry 153's reading: today's recipe at 10, 30, 60 and 120 s on fleet88 and other16.
Rule 1: each run's references equal its base run's, every plan costs at most its budget, and the 120 s rows
against the entries that measured them (fleet88: 101 alone, 131 with use; other16: 101 alone, 130 with use).
Rule 2: the curve, each unit's draws averaged, 600 s from entries 143 (fleet88) and 142/144 (other16). Rule 3:
today's over entry 26's recipe per unit on fleet88 (entry 79's `fleet88_grouped`), and how that gain moves
from 120 s to shorter budgets. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry153/analyse.py
"""

import runpy
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
GPU = HERE.parent
REPORTS = GPU.parent
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
BUDGETS = (10.0, 30.0, 60.0, 120.0)
ALONE, USE = "response@cover_informative", "response+use@cover_informative"
DRAWS, O16_FOLDS, F88_FOLDS = (0, 1, 2), (0, 1, 2, 3), (0, 1)
Rows = list[dict[str, Any]]
references = runpy.run_path(str(GPU / "entry151" / "analyse.py"))["references"]


@cache
def metrics(run: Path) -> Rows:
    """A run's rows, read once (several rules and entry 154 read the same runs)."""
    return read_json(run / "metrics.json")["results"]


def f88(root: Path, k: int) -> Path:
    return root / f"fleet88_seed{k}"


def o16(root: Path, d: int, k: int) -> Path:
    return root / f"other16_severe_d{d}" / f"other16_seed{k}"


def o16_600(d: int, k: int) -> Path:
    """other16 at 600 s with today's recipe: draw 0 is entry 142's run, draws 1-2 entry 144's."""
    return o16(GPU / ("entry142" if d == 0 else "entry144"), d, k)


def moved(new: Rows, old: Rows, method: str) -> tuple[int, float, float]:
    """How many of `method`'s 120 s RMSEs two runs share, the most one moved (relative), the mean's move."""
    def rmses(got: Rows) -> dict[tuple[str, str], float]:
        return {(r["unit"], key): r[key] for r in got
                if r["method"] == method and r.get("budget_s") == 120.0 for key in KEYS.values()}
    a, b = rmses(new), rmses(old)
    shared = sorted(set(a) & set(b))
    rel = np.array([a[s] / b[s] - 1 for s in shared])
    return len(shared), float(np.max(np.abs(rel))), float(np.mean([a[s] for s in shared])
                                                           / np.mean([b[s] for s in shared]) - 1)


def checked(run: Path, base: Path, methods: tuple[str, ...]) -> str:
    """Rule 1's part every entry shares: whether the run's references equal its base run's, and how many of
    `methods`' plans cost more than their budget."""
    got = metrics(run)
    equal = references(got) == references(metrics(base))
    over = [r for r in got if r["method"] in methods and r["calib_seconds"] > r["budget_s"] + 1e-6]
    return f"references {'equal' if equal else 'DIFFER'}; {len(over)} plans over budget"


def same_references(pairs: list[tuple[Path, Path]]) -> str:
    """'equal' where each (run, base) pair's references are equal, else 'DIFFER'."""
    return "equal" if all(references(metrics(a)) == references(metrics(b)) for a, b in pairs) else "DIFFER"


def gate(name: str, run: Path, base: Path, before: dict[str, Path]) -> None:
    """Rule 1 for one run: its references against its base run's, its plans' robot time, its 120 s rows."""
    got = metrics(run)
    parts = []
    for method, old in before.items():
        n, most, mean = moved(got, metrics(old), method)
        parts.append(f"{method} vs {old.relative_to(GPU).parts[0]}: {n} RMSEs, most moved {most:.2e}, "
                     f"mean {mean:+.2e}")
    print(f"rule 1, {name}: {checked(run, base, (ALONE, USE))}; " + "; ".join(parts))


def curve(rows: Rows, methods: tuple[str, ...], budgets: tuple[float, ...]) -> dict[tuple[str, float], str]:
    """(method, budget) -> 'force m [lo, hi] / angle m [lo, hi] (n units)', each unit's draws averaged."""
    per = {label: unit_ratios(rows, key) for label, key in KEYS.items()}
    out = {}
    for m in methods:
        for b in budgets:
            if (m, b) not in per["force"]:
                continue
            cells = [mean_interval(list(per[label][(m, b)].values())) for label in KEYS]
            out[(m, b)] = (" / ".join(f"{c[0]:.3f}x [{c[1]:.2f}, {c[2]:.2f}]" for c in cells)
                           + f" ({len(per['force'][(m, b)])} units)")
    return out


def table(name: str, mine: Rows, at600: Rows, old: Rows, old_methods: dict[str, str]) -> None:
    """Rule 2: today's curve beside entry 26's recipe, force / angle."""
    today = curve(mine, (ALONE, USE), BUDGETS) | curve(at600, (ALONE, USE), (600.0,))
    before = curve(old, tuple(old_methods.values()), BUDGETS + (600.0,))
    print(f"rule 2, {name}: force / angle, mean over units [95%]")
    print("| robot-s | plan alone | with ordinary use | entry 26's recipe, alone | with use |")
    print("|---|---|---|---|---|")
    for b in BUDGETS + (600.0,):
        print(f"| {b:g} | {today.get((ALONE, b), '')} | {today.get((USE, b), '')} | "
              f"{before.get((old_methods['alone'], b), '')} | {before.get((old_methods['use'], b), '')} |")


def gains(mine: Rows, old: Rows, method: str, old_method: str) -> dict[float, dict[str, float]]:
    """budget -> {unit: today's force ratio over entry 26's}, the same references."""
    now, then = unit_ratios(mine, KEYS["force"]), unit_ratios(old, KEYS["force"])
    return {b: {u: now[(method, b)][u] / then[(old_method, b)][u] for u in now[(method, b)]}
            for b in BUDGETS if (method, b) in now and (old_method, b) in then}


def rule3(mine: Rows, old: Rows) -> None:
    """Rule 3 on fleet88, the plan alone: g(b) and g(b) / g(120) per unit."""
    g = gains(mine, old, ALONE, "response@cover")
    print("rule 3, fleet88, the plan alone, force: today's over entry 26's recipe per unit, g(b)")
    for b, per in g.items():
        print(f"  g({b:g}) = x{paired_text(list(per.values()))}")
    for b in BUDGETS[:-1]:
        print(f"  g({b:g}) / g(120) = x{paired_text([g[b][u] / g[120.0][u] for u in g[b]])}")


def main() -> None:
    start = REPORTS / "cross_sensor_response_start"
    for k in F88_FOLDS:
        gate(f"fleet88 fold {k}", f88(HERE, k), f88(start, k),
             {ALONE: f88(GPU / "entry101" / "fleet88_cpu", k), USE: f88(GPU / "entry131", k)})
    draws = [d for d in DRAWS if all((o16(HERE, d, k) / "metrics.json").is_file() for k in O16_FOLDS)]
    for d in draws:
        for k in O16_FOLDS:
            gate(f"other16 draw {d} fold {k}", o16(HERE, d, k), start / f"other16_seed{k}",
                 {ALONE: o16(GPU / "entry101", d, k), USE: o16(GPU / "entry130", d, k)})
    budgets = REPORTS / "cross_sensor_budgets"
    f88_mine = [r for k in F88_FOLDS for r in metrics(f88(HERE, k))]
    alone = [(budgets / f"fleet88_grouped_seed{k}", f88(start, k)) for k in F88_FOLDS]
    print(f"entry 26's recipe, the plan alone (entry 79): references {same_references(alone)}")
    with_use = [(budgets / f"{name}{k}", f88(start, k)) for k in F88_FOLDS
                for name in ("fleet88_use30_seed", "fleet88_use60_seed")]
    with_use += [(f88(REPORTS / "cross_sensor_response_label_free", k), f88(start, k))  # entry 46, 120 s
                 for k in F88_FOLDS]
    print(f"entry 26's recipe with ordinary use (entries 46, 76-77): references {same_references(with_use)}")
    f88_old = [r for run, _ in alone for r in metrics(run)]
    f88_old += [{**r, "method": "old_use+use@cover"} for run, _ in with_use for r in metrics(run)
                if r["method"] == "response+use@cover"]
    table("fleet88 (88 units)", f88_mine, [r for k in F88_FOLDS for r in metrics(f88(GPU / "entry143", k))],
          f88_old, {"alone": "response@cover", "use": "old_use+use@cover"})
    o16_mine = [r for d in draws for k in O16_FOLDS for r in metrics(o16(HERE, d, k))]
    o16_old = [r for k in O16_FOLDS for r in metrics(budgets / f"other16_use_grouped_seed{k}")]
    table(f"other16 (16 units, draws {', '.join(map(str, draws))} averaged; entry 26's columns: entry 79's "
          "1,034-unit models, one draw)", o16_mine,
          [r for d in draws for k in O16_FOLDS for r in metrics(o16_600(d, k))], o16_old,
          {"alone": "response@cover", "use": "response+use@cover"})
    rule3(f88_mine, f88_old)


if __name__ == "__main__":
    main()
