"""Research log entry 207's reading of logs/time_shipped.log: rule 1 (calm: every probe at least 85
GFLOP/s), rule 2 (per registry, the median and the largest `wall_s` against 10 s) and rule 3 (each unit's
networks the same in every round).

    python reports/cross_sensor_response_gpu/entry207/analyse.py > \\
        reports/cross_sensor_response_gpu/entry207/logs/analyse.log
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

LOG = Path(__file__).parent / "logs" / "time_shipped.log"
TARGET_S, CALM_GFLOPS = 10.0, 85.0


def main() -> None:
    rows = [line.split() for line in LOG.read_text().splitlines() if line.strip()]
    # FOLD UNIT round R wall_s S core_gflops G model H
    probes = np.array([float(r[7]) for r in rows])
    calm = "yes" if probes.min() >= CALM_GFLOPS else "no"
    print(f"rule 1: {len(rows)} calibrations, probes {probes.min():.1f}-{probes.max():.1f} GFLOP/s "
          f"({int(np.sum(probes < CALM_GFLOPS))} below {CALM_GFLOPS:g}): calm {calm}")
    print("\nrule 2, wall_s per registry")
    for fold, name in (("f0", "fleet88 fold 0 (SIM41)"), ("o0", "other16 fold 0 (SIM24)")):
        w = np.sort([float(r[5]) for r in rows if r[0] == fold])
        verdict = "all under 10 s" if w.max() < TARGET_S else f"{int(np.sum(w >= TARGET_S))} at or over 10 s"
        print(f"  {name}: {' '.join(f'{x:.2f}' for x in w)}; median {np.median(w):.2f} s; {verdict}")
    models: dict[str, set[str]] = {}
    for r in rows:
        models.setdefault(r[1], set()).add(r[9])
    same = sum(len(m) == 1 for m in models.values())
    print(f"\nrule 3: {same} of {len(models)} units' networks the same in every round")


if __name__ == "__main__":
    main()
