"""Research log entry 165's reading: the registries' held-out units given references of three starts.
Rule 1: start 0's kept fit is the run's own reference. Rule 2: the kept reference over the run's, per unit,
on fleet88, other16 and pooled with entry 164's 64 fresh units. Rule 3: every target's committed rows against
the kept references beside their figures against one start, with the verdict against the goal. Usage, from
the repository root:

    python reports/cross_sensor_response_gpu/entry165/analyse.py
"""

import runpy
from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
GPU = HERE.parent
E153 = runpy.run_path(str(GPU / "entry153" / "analyse.py"))
E164 = runpy.run_path(str(GPU / "entry164" / "analyse.py"))
KEYS, ALONE, USE = E153["KEYS"], E153["ALONE"], E153["USE"]
DESIGNED, DESIGNED_USE = "response@designed", "response+use@designed"
FOLDS = {"fleet88": (0, 1), "other16": (0, 1, 2, 3)}
DRAWS = (0, 1, 2)
START = GPU.parent / "cross_sensor_response_start"
Rows = list[dict[str, Any]]
# (target, the runs' role in `runs`, method, budget s, goal on the mean); the last two after the rules
TARGETS = [("120 s + 600 s of ordinary use", "use", USE, 120.0, 1.10),
           ("120 s, the plan's labels alone", "alone", ALONE, 120.0, 1.10),
           ("120 s, the designed plan + ordinary use", "designed", DESIGNED_USE, 120.0, 1.10),
           ("120 s, the designed plan alone", "designed", DESIGNED, 120.0, 1.10),
           ("60 s + 600 s of ordinary use", "budgets", USE, 60.0, 1.10),
           ("30 s + 600 s of ordinary use", "budgets", USE, 30.0, 1.10),
           ("60 s, the plan alone", "budgets", ALONE, 60.0, 1.10),
           ("600 s of robot time", "at600", ALONE, 600.0, 1.0),
           ("600 s, with ordinary use", "at600", USE, 600.0, 1.0),
           ("600 s, the designed plan", "designed600", DESIGNED, 600.0, 1.0),
           ("600 s, the designed plan + ordinary use", "designed600", DESIGNED_USE, 600.0, 1.0),
           ("60 s, the designed plan + ordinary use", "designed_short", DESIGNED_USE, 60.0, 1.10),
           ("30 s, the designed plan + ordinary use", "designed_short", DESIGNED_USE, 30.0, 1.10)]


def new_references(registry: str) -> tuple[dict[tuple[str, int], dict], Rows]:
    """(unit, seed) -> the kept reference row, and every fit's row (with its seed), over the registry's
    folds."""
    kept, trials = {}, []
    for k in FOLDS[registry]:
        got = read_json(HERE / f"{registry}_seed{k}" / "references.json")
        kept |= {(r["unit"], r["seed"]): r for r in got["rows"]}
        trials += [{**t, "seed": got["seed"]} for t in got["trials"]]
    return kept, trials


def old_references(registry: str) -> dict[tuple[str, int], dict]:
    """(unit, seed) -> the reference row of the run every target's rows keep."""
    rows = [r for k in FOLDS[registry] for r in E153["metrics"](START / f"{registry}_seed{k}")]
    return {(r["unit"], r["seed"]): r for r in rows if r["method"] == "per_unit"}


def start0(trials: Rows) -> dict[tuple[str, int], dict]:
    """(unit, seed) -> the reference today's pipeline trains from one start: start 0's fit with the lowest
    validation loss, as a per_unit row."""
    out: dict[tuple[str, int], dict] = {}
    for t in trials:
        c = (t["unit"], t["seed"])
        if t["start"] == 0 and (c not in out or t["val_loss"] < out[c]["val_loss"]):
            out[c] = {**t, "method": "per_unit"}
    return out


def gate(today: dict, old: dict) -> list[str]:
    """Rule 1: the (unit, seed)s whose start-0 fit with the lowest validation loss (`start0`) is not the run's
    reference (its learning rate, or force or angle RMSE by a relative 1e-6 or more)."""
    bad = []
    for (unit, seed), ref in old.items():
        best = today.get((unit, seed))
        if best is None:
            bad.append(f"{unit} seed {seed}: no fit")
        elif best["lr"] != ref.get("reference_lr") or any(abs(best[k] / ref[k] - 1) >= 1e-6
                                                           for k in KEYS.values()):
            bad.append(f"{unit} seed {seed}")
    return bad


def gains(new: dict, old: dict) -> dict[str, list[float]]:
    """target -> per unit, the kept reference's RMSE over the run's."""
    return {name: [new[c][key] / old[c][key] for c in sorted(old)] for name, key in KEYS.items()}


def swapped(rows: Rows, refs: dict[tuple[str, int], dict]) -> Rows:
    """`rows` with each per_unit row replaced by the kept reference of the same unit and seed."""
    out = [r for r in rows if r["method"] != "per_unit"]
    return out + [refs[r["unit"], r["seed"]] for r in rows if r["method"] == "per_unit"]


def cell(rows: Rows, method: str, budget: float) -> tuple[str, list[tuple[float, float, float]]]:
    """'force m [lo, hi] / angle m [lo, hi]', and (mean, lower, upper) over units of each."""
    got = [mean_interval(list(unit_ratios(rows, key)[method, budget].values())) for key in KEYS.values()]
    return " / ".join(f"{m:.3f}x [{lo:.2f}, {hi:.2f}]" for m, lo, hi in got), got


def runs(registry: str) -> dict[str, tuple[list[Path], str, float, float]]:
    """target -> (the runs its committed figure reads, method, budget, goal on the mean)."""
    o16, f88 = E153["o16"], E153["f88"]
    roots = {"alone": "entry101", "use": "entry131" if registry == "fleet88" else "entry130",
             "budgets": "entry153", "designed": "entry146/at120", "designed600": "entry146/at600",
             "designed_short": "entry154"}
    if registry == "fleet88":
        roots |= {"alone": "entry101/fleet88_cpu", "at600": "entry143"}
        at = {role: [f88(GPU / r, k) for k in FOLDS[registry]] for role, r in roots.items()}
    else:
        at = {role: [o16(GPU / r, d, k) for d in DRAWS for k in FOLDS[registry]] for role, r in roots.items()}
        at["at600"] = [E153["o16_600"](d, k) for d in DRAWS for k in FOLDS[registry]]
    return {target: (at[role], method, budget, goal) for target, role, method, budget, goal in TARGETS}


def verdict(got: list[tuple[float, float, float]], goal: float) -> str:
    """Met, or missed by how much, in force and angle alike: below the goal on the mean where it is 1.0, else
    the mean at most the goal and the upper bound at most 1.25."""
    if goal < 1.05:
        miss = max(m - goal for m, _, _ in got)
        return "met" if miss < 0 else f"missed by {miss:.3f}"
    miss = max(max(m - goal, hi - 1.25) for m, _, hi in got)
    return "met" if miss <= 0 else f"missed by {miss:.3f}"


def rule3(registry: str, new: dict, today: dict) -> None:
    """Every target's committed rows against the run's references (one start), today's one start and the
    references kept over three starts."""
    print(f"\nrule 3, {registry}: force / angle, mean over units [95%]; the verdict in force and angle")
    print("| target | against the run's references | verdict | against today's one start | against three "
          "starts | verdict |")
    print("|---|---|---|---|---|---|")
    for target, (paths, method, budget, goal) in runs(registry).items():
        rows = [r for p in paths for r in E153["metrics"](p)]
        (one, got1), (now, _), (three, got3) = (cell(swapped(rows, refs) if refs else rows, method, budget)
                                                 for refs in (None, today, new))
        print(f"| {target} | {one} | {verdict(got1, goal)} | {now} | {three} | {verdict(got3, goal)} |")


def exploratory(trials: Rows, registry: str) -> None:
    """After the rules: the spread over starts at each unit's kept learning rate, and how often the kept fit
    is the one with the best test RMSE in force."""
    by: dict[tuple[str, int], Rows] = {}
    for t in trials:
        by.setdefault((t["unit"], t["seed"]), []).append(t)
    spread, best = [], 0
    for fits in by.values():
        kept = min(fits, key=lambda t: t["val_loss"])
        same_lr = [np.log(t[KEYS["force"]]) for t in fits if t["lr"] == kept["lr"]]
        spread.append(np.std(same_lr, ddof=1))
        best += kept is min(fits, key=lambda t: t[KEYS["force"]])
    print(f"exploratory, {registry}: over starts at the kept learning rate a reference spreads by "
          f"{np.exp(np.mean(spread)) - 1:.1%}; the kept fit is the best in test force for {best} of "
          f"{len(by)}")


def main() -> None:
    pooled: dict[str, list[float]] = {name: [] for name in KEYS}
    pooled_today: dict[str, list[float]] = {name: [] for name in KEYS}
    refs = {}
    for registry in FOLDS:
        new, trials = new_references(registry)
        old, today = old_references(registry), start0(trials)
        bad = gate(today, old)
        print(f"rule 1, {registry}: {len(old) - len(bad)} of {len(old)} units' start-0 fits give the run's "
              f"reference back" + (f"; DIFFER: {bad}" if bad else ""))
        g = gains(new, old)
        print(f"rule 2, {registry} ({len(old)} units), kept over the run's reference per unit: "
              + "; ".join(f"{name} x{paired_text(v)}" for name, v in g.items()))
        drift, g_today = gains(today, old), gains(new, today)
        print("  after the rules: today's one start over the run's reference "
              + "; ".join(f"{name} x{paired_text(v)}" for name, v in drift.items())
              + "; kept over three starts over today's one start "
              + "; ".join(f"{name} x{paired_text(v)}" for name, v in g_today.items()))
        others = sum(r["reference_start"] != 0 for r in new.values())
        print(f"  {others} of {len(new)} units keep a start other than 0")
        for name in KEYS:
            pooled[name] += g[name]
            pooled_today[name] += g_today[name]
        refs[registry] = (new, trials, today)
    got, old = E164["starts"](), E164["before"]()
    chosen = E164["kept"](got, sorted(old))
    for name, key in KEYS.items():
        pooled[name] += [chosen[u][key] / old[u][key] for u in sorted(old)]
        pooled_today[name] += [chosen[u][key] / old[u][key] for u in sorted(old)]  # its gate held
    for label, got in (("", pooled), (" (over today's one start; after the rules)", pooled_today)):
        m, lo, hi = paired_interval(got["force"])
        print(f"rule 2, pooled with entry 164's 64 fresh units ({len(got['force'])} units){label}: force "
              f"x{m:.3f} [{lo:.3f}, {hi:.3f}]; angle x{paired_text(got['angle'])}; rule 4: "
              + ("the interval lies wholly below 1" if hi < 1 else "the interval reaches 1"))
    for registry, (new, _, today) in refs.items():
        rule3(registry, new, today)
    print()
    for registry, (_, trials, _) in refs.items():
        exploratory(trials, registry)


if __name__ == "__main__":
    main()
