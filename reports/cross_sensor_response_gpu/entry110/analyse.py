"""Research log entry 110: entry 108's rescoring with every fleet88 unit tested on both its sessions
(`splits.test_rows: all_sessions`: its main rows at its test patches and its test session's there), run twice:
from the commit before entry 109's float32 kernel with the option applied (`fleet88r_both_f64`, entry 106's
networks: what the rules were written for) and with today's code (`fleet88r_both`, whose float32 kernel moves
every network by training noise, so rule 1 fails there by construction). Per run it prints rule 1 (the plans'
own half-widths against entry 106's; each held-out unit's test rows against entry 106's plus entry 108's),
rule 2 (each fold's factor and margin, and the target on both sessions' rows, per method, with its verdict),
and, deciding nothing, the unit-outputs below 0.80 in either single session with their coverage here. The
rescoring keeps the run's per-unit references (`--paired-only`), so no ratio to them is printed. From the
repository root:

    python reports/cross_sensor_response_gpu/entry110/analyse.py
"""

from __future__ import annotations

import runpy
from pathlib import Path
from typing import Any

import numpy as np

from anytip.uncertainty.fleet_margin import IN_BAND_SHARE

G = Path("reports/cross_sensor_response_gpu")
RUNS = {"entry 106's networks (fleet88r_both_f64), the entry's runs":
        [G / f"entry110/fleet88r_both_f64/fleet88_seed{k}" for k in (0, 1)],
        "today's code, the float32 kernel (fleet88r_both), also read":
        [G / f"entry110/fleet88r_both/fleet88_seed{k}" for k in (0, 1)]}
ONE_SESSION = {"entry 106": [G / f"entry106/fleet88_cpu_use/fleet88_seed{k}" for k in (0, 1)],
               "entry 108": [G / f"entry108/fleet88r_use/fleet88_seed{k}" for k in (0, 1)]}
ANALYSE_106 = runpy.run_path(str(G / "entry106/analyse.py"))  # rows_by_unit, same, below, factors
ANALYSE_108 = runpy.run_path(str(G / "entry108/analyse.py"))  # intervals, METHODS, OUTPUTS
rows_by_unit, METHODS, OUTPUTS = ANALYSE_106["rows_by_unit"], ANALYSE_108["METHODS"], ANALYSE_108["OUTPUTS"]
FLOOR, LOW, HIGH = ANALYSE_108["FLOOR"], ANALYSE_108["LOW"], ANALYSE_108["HIGH"]


def rule_1(runs: list[Path]) -> str:
    """The plans' own half-widths against entry 106's, and the test rows against entry 106's plus 108's."""
    keys = [f"{o}_halfwidth" for o in OUTPUTS]
    lines = []
    for m in METHODS:
        now, (a, b) = rows_by_unit(runs, m), (rows_by_unit(one, m) for one in ONE_SESSION.values())
        rows_sum = sum(now[u]["interval_test_rows"] == a[u]["interval_test_rows"] + b[u]["interval_test_rows"]
                       for u in now)
        lines.append(f"  {m} own half-widths: {ANALYSE_106['same'](now, a, keys)}; test rows = entry 106's "
                     f"+ entry 108's in {rows_sum} of {len(now)} units")
    return "rule 1:\n" + "\n".join(lines)


def met(rows: dict[str, dict[str, Any]]) -> bool:
    """The interval target on rows by unit (`margin_` coverages): at least `IN_BAND_SHARE` of the
    unit-outputs in the band and none below the floor."""
    cover = np.array([[r[f"{o}_margin_coverage"] for o in OUTPUTS] for r in rows.values()])
    return bool(np.mean((cover >= LOW) & (cover <= HIGH)) >= IN_BAND_SHARE and not (cover < FLOOR).any())


def verdict(runs: list[Path], method: str) -> str:
    """Rule 2's verdict on both sessions' rows: at least 90% of unit-outputs in the band and none below."""
    return f"  {method}: {'met' if met(rows_by_unit(runs, method)) else 'missed'}"


def single_session_tails(runs: list[Path]) -> str:
    """The held-out unit-outputs below the floor in either single session, with their coverage here."""
    lines = []
    for m in METHODS:
        here = rows_by_unit(runs, m)
        for name, runs in ONE_SESSION.items():
            for cell in ANALYSE_106["below"](rows_by_unit(runs, m), "margin"):
                unit, output, was = cell.split()
                lines.append(f"  {m}: {unit} {output} {was} in {name}, "
                             f"{here[unit][f'{output}_margin_coverage']:.3f} on both sessions")
    return "\n".join(lines) or "  none"


def main() -> None:
    for name, runs in RUNS.items():
        print(f"== {name}\n{rule_1(runs)}")
        print("\nrule 2, the target on both sessions' rows:")
        for seed, run in enumerate(runs):
            print(ANALYSE_106["factors"](run, seed))
        for m in METHODS:
            print(ANALYSE_108["intervals"](runs, m))
        for m in METHODS:
            print(verdict(runs, m))
        print("\nalso read (decides nothing): unit-outputs below 0.80 in one session, here")
        print(single_session_tails(runs) + "\n")


if __name__ == "__main__":
    main()
