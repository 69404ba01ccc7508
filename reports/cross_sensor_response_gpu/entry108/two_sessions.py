"""Research log entry 108, an exploratory reading after its result (the held-out units' coverage in both
sessions was known; it decides nothing): would learners tested in two sessions give the fleet factor and its
margin less of one session's draw? Each fold's 28 learners (4 validation and 24 factor units: the same
networks and plans in entries 106 and 108) get, per output, the geometric mean of the half-widths their two
sessions' test rows needed (at the nominal level, the floor and the band's edges; an approximation of what the
two sessions' rows together would need). Their factor and leave-one-out margin (`fleet_margin.pooled_factor`)
then widen each held-out unit's own half-width, scored against each session's test rows alone. From the
repository root:

    python reports/cross_sensor_response_gpu/entry108/two_sessions.py
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

from anytip.pipelines.cross_sensor_jobs import band_edges, needed_key
from anytip.uncertainty.fleet_margin import Learner, pooled_factor

G = Path("reports/cross_sensor_response_gpu")
SESSIONS = {"entry 106's test rows": [G / f"entry106/fleet88_cpu_use/fleet88_seed{k}" for k in (0, 1)],
            "the session of their own": [G / f"entry108/fleet88r_use/fleet88_seed{k}" for k in (0, 1)]}
METHODS = {"response+use@cover_informative": "use_units_by_strategy",
           "response@cover_informative": "units_by_strategy"}
OUTPUTS = ("fx", "fy", "fz", "theta", "phi")
FLOOR, LOW, HIGH = band_edges(0.9)
FOLD_TABLE = runpy.run_path("scripts/fold_table.py")  # its functions, not its command line


def learners(runs: list[Path], fold: int, key: str) -> dict[str, Learner]:
    """The fold's learners as its response model recorded them."""
    return FOLD_TABLE["fold_learners"]([runs[fold]])[str(runs[fold]), fold][key, "cover_informative", "120"]


def both(a: Learner, b: Learner) -> Learner:
    """One learner from its two sessions: the same own half-width, the geometric mean of the needed ones."""
    if not np.array_equal(a.own, b.own):
        raise SystemExit("a learner's own half-widths differ between the sessions")
    return Learner(a.own, *(np.sqrt(getattr(a, f) * getattr(b, f)) for f in Learner._fields[1:]))


def scored(method: str, rule: str) -> str:
    """Per session, the held-out unit-outputs in the band and below the floor under `rule`'s factor and margin
    (`one`: each session's own learners, as recorded; `two`: the learners of both sessions joined)."""
    out = []
    for name, runs in SESSIONS.items():
        in_band, below, margins = [], [], []
        for fold in (0, 1):
            key = METHODS[method]
            mine = learners(runs, fold, key)
            if rule == "two":
                other = next(r for n, r in SESSIONS.items() if n != name)
                theirs = learners(other, fold, key)
                mine = {u: both(mine[u], theirs[u]) for u in sorted(mine)}
            factor, choice = pooled_factor(list(mine.values()))
            margins.append(f"{choice.margin:g}")
            rows = [r for r in FOLD_TABLE["rows_of"]([runs[fold]]) if r["method"] == method]
            for r in rows:
                for d, o in enumerate(OUTPUTS):
                    w = r[f"{o}_halfwidth"] * factor[d] * choice.margin
                    in_band.append(r[needed_key(o, LOW)] <= w <= r[needed_key(o, HIGH)])
                    if w < r[needed_key(o, FLOOR)]:
                        below.append(f"{r['unit']} {o}")
        out.append(f"    {name}: margins {', '.join(margins)}; {np.mean(in_band):.1%} of {len(in_band)} "
                   f"in band, {len(below)} below {FLOOR:.2f} ({', '.join(below) or 'none'})")
    return "\n".join(out)


def main() -> None:
    for method in METHODS:
        print(f"{method}:")
        for rule, label in (("one", "learners of one session (the recipe)"),
                            ("two", "learners of both sessions")):
            print(f"  {label}:\n{scored(method, rule)}")


if __name__ == "__main__":
    main()
