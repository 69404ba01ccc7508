"""Research log entry 108: entry 106's arm rescored with every fleet88 unit tested in a session of its own
(`retest`). Prints rule 1 (the plans' own half-widths against entry 106's), rule 2's reading (per output, the
correlation over the 88 held-out units of log(needed80 / own) between entry 106's test rows and the
session's, SIM40-019 fy's rank there, and the verdict the entry wrote down), and, deciding nothing, the
intervals on the session's rows: each fold's factor and margin, the share of unit-outputs in the band, those
below the floor, and an exact method's share. The rescoring keeps the run's per-unit references, scored on
its own test rows (`--paired-only`), so no ratio to them is printed. From the repository root:

    python reports/cross_sensor_response_gpu/entry108/analyse.py
"""

from __future__ import annotations

import runpy
from pathlib import Path
from typing import Any

import numpy as np

from anytip.pipelines.cross_sensor_jobs import band_edges
from anytip.report.cross_sensor import exact_share

G = Path("reports/cross_sensor_response_gpu")
RUNS = [G / f"entry108/fleet88r_use/fleet88_seed{k}" for k in (0, 1)]
BEFORE = [G / f"entry106/fleet88_cpu_use/fleet88_seed{k}" for k in (0, 1)]
METHODS = ("response+use@cover_informative", "response@cover_informative")
OUTPUTS = ("fx", "fy", "fz", "theta", "phi")
WATCHED = ("SIM40-019", "fy")
ALSO = ("SIM40-019", "SIM40-006")  # the two below 0.80 in entry 106
FLOOR, LOW, HIGH = band_edges(0.9)
FOLD_TABLE = runpy.run_path("scripts/fold_table.py")  # its functions, not its command line
ANALYSE_106 = runpy.run_path(str(G / "entry106/analyse.py"))  # its rows_by_unit, same, below, factors
rows_by_unit = ANALYSE_106["rows_by_unit"]
row_log_ratio = runpy.run_path(str(G / "entry108/tail_persistence.py"))["log_ratio"]


def log_ratio(rows: dict[str, dict[str, Any]]) -> np.ndarray:
    """(U, D) log(needed80 / own) per unit (sorted by name) and output."""
    return np.stack([row_log_ratio(rows[u]) for u in sorted(rows)])


def rank(values: np.ndarray, units: list[str], unit: str) -> int:
    """`unit`'s rank among `units` by `values` (U,), 1 the largest."""
    return int((values > values[units.index(unit)]).sum()) + 1


def rule_1() -> str:
    """The plans' own half-widths of every held-out unit against entry 106's."""
    keys = [f"{o}_halfwidth" for o in OUTPUTS]
    return "rule 1:\n" + "\n".join(
        f"  {m} own half-widths: {ANALYSE_106['same'](rows_by_unit(RUNS, m), rows_by_unit(BEFORE, m), keys)}"
        for m in METHODS)


def rule_2(method: str = METHODS[0]) -> str:
    """The correlations, the watched unit-output's rank, and the verdict written down before the runs (for
    the recipe's method; for another, the same figures read alone)."""
    now, then = rows_by_unit(RUNS, method), rows_by_unit(BEFORE, method)
    a, b = log_ratio(then), log_ratio(now)
    corr = [float(np.corrcoef(a[:, d], b[:, d])[0, 1]) for d in range(len(OUTPUTS))]
    units, d = sorted(now), OUTPUTS.index(WATCHED[1])
    now_rank, rank_then = rank(b[:, d], units, WATCHED[0]), rank(a[:, d], units, WATCHED[0])
    other = METHODS[1] if method == METHODS[0] else METHODS[0]
    same_rows = log_ratio(rows_by_unit(BEFORE, other))
    ref = [float(np.corrcoef(a[:, k], same_rows[:, k])[0, 1]) for k in range(len(OUTPUTS))]
    fy = corr[d]
    verdict = ("the unit" if now_rank <= 5 and fy >= 0.5 else "the session" if now_rank > 10 and fy < 0.3
               else "undecided")
    top = [units[i] for i in np.argsort(-b[:, d])[:5]]
    # where both sessions' noise is alike, 1 - correlation is the session's share of the units' variance
    share = ", ".join(f"{o} {1 - c:.2f}" for o, c in zip(OUTPUTS, corr, strict=True))
    ranks = ", ".join(f"{u} {rank(a[:, d], units, u)} -> {rank(b[:, d], units, u)}" for u in ALSO)
    return (f"rule 2 ({method}, {len(units)} held-out units):\n"
            f"  correlation of log(needed80 / own), entry 106's test rows against the session's: "
            + ", ".join(f"{o} {c:.2f}" for o, c in zip(OUTPUTS, corr, strict=True))
            + f"\n  for reference, entry 106's {method} against its {other}, on the same test rows: "
            + ", ".join(f"{o} {c:.2f}" for o, c in zip(OUTPUTS, ref, strict=True))
            + f"\n  {' '.join(WATCHED)}: rank {now_rank} of {len(units)} in the session (entry 106: "
            f"{rank_then}); the session's top 5 in fy: {', '.join(top)}\n  verdict: {verdict}\n"
            f"  also read: 1 - correlation (the session's share of the variance, if alike in both): {share}\n"
            f"  fy ranks, entry 106 -> the session: {ranks}")


def intervals(runs: list[Path], method: str) -> str:
    """The runs' intervals (factor x margin, as recorded): share in band, those below the floor, and an
    exact method's share in band."""
    rows = rows_by_unit(runs, method)
    cover = np.array([[r[f"{o}_margin_coverage"] for o in OUTPUTS] for r in rows.values()])
    low = ANALYSE_106["below"](rows, "margin")
    exact = exact_share(list(rows.values()))
    return (f"  {method}: {np.mean((cover >= LOW) & (cover <= HIGH)):.1%} of {cover.size} in [{LOW:.2f}, "
            f"{HIGH:.2f}], {len(low)} below {FLOOR:.2f} ({', '.join(low) or 'none'}); "
            f"lowest {cover.min():.3f}; an exact method {exact:.0%} in band")


def main() -> None:
    print(rule_1())
    print()
    print(rule_2())
    print("\nalso read (decides nothing), the plan alone:")
    print(rule_2(METHODS[1]))
    print("\nalso read (decides nothing): the intervals on the session's rows")
    for seed, run in enumerate(RUNS):
        print(ANALYSE_106["factors"](run, seed))
    for m in METHODS:
        print(intervals(RUNS, m))
    print("entry 106's, on its own test rows:")
    for m in METHODS:
        print(intervals(BEFORE, m))


if __name__ == "__main__":
    main()
