"""Research log entry 200's reading of logs/time_calibrate.log: rule 1 (calm: every probe at least 85 GFLOP/s
and the old code's median `wall_s` per arm within x1.05 of entry 172's code's), rule 2 (the new code's nine
`wall_s` per arm against 10 s) and rule 3 (new over old, paired, as entries 172 and 196 read it).

    python reports/cross_sensor_response_gpu/entry200/analyse.py > \\
        reports/cross_sensor_response_gpu/entry200/logs/analyse.log
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
timing_line = runpy.run_path(str(HERE.parent / "entry171" / "analyse.py"))["timing_line"]
E172 = runpy.run_path(str(HERE.parent / "entry172" / "analyse.py"))
# another entry's timing log (entry 203: `analyse.py entry203`) or this entry's own; and the entry whose new
# code is that timing's old code (entry 204: `analyse.py entry204 entry203`; default entry 172)
ENTRY = sys.argv[1] if len(sys.argv) > 1 else "entry200"
DAY = sys.argv[2] if len(sys.argv) > 2 else "entry172"
LOG = HERE.parent / ENTRY / "logs" / "time_calibrate.log"
OLD_DAY = HERE.parent / DAY / "logs" / "time_calibrate.log"
TARGET_S, CALM_GFLOPS, CALM_RATIO = 10.0, 85.0, 1.05


def walls(log: Path, code: str, arm: str) -> np.ndarray:
    """The `wall_s` of `code`'s calibrations of `arm` in `log`."""
    got = [timing_line(line) for line in log.read_text().splitlines()]
    return np.array([float(t["wall_s"]) for t in got if t and t["code"] == code and t["arm"] == arm])


def main() -> None:
    probes = [float(t["core_gflops"]) for t in map(timing_line, LOG.read_text().splitlines()) if t]
    print(f"rule 1: {len(probes)} calibrations, probes {min(probes):.1f}-{max(probes):.1f} GFLOP/s "
          f"({sum(p < CALM_GFLOPS for p in probes)} below {CALM_GFLOPS:g})")
    calm = min(probes) >= CALM_GFLOPS
    for arm in ("alone", "use"):
        ratio = np.median(walls(LOG, "old", arm)) / np.median(walls(OLD_DAY, "new", arm))
        calm &= 1 / CALM_RATIO <= ratio <= CALM_RATIO
        day = DAY.replace("entry", "entry ")
        print(f"  {arm}: the old code's median over {day}'s code's on its day x{ratio:.3f}")
    print(f"  calm: {'yes' if calm else 'no'}")
    print("\nrule 2, the new code's wall_s per arm")
    for arm in ("alone", "use"):
        new = np.sort(walls(LOG, "new", arm))
        verdict = ("all under 10 s" if new.max() < TARGET_S
                   else f"{int(np.sum(new >= TARGET_S))} of {len(new)} at or over 10 s, the largest "
                        f"x{new.max() / TARGET_S:.3f}")
        print(f"  {arm}: {' '.join(f'{w:.2f}' for w in new)}; median {np.median(new):.2f} s; {verdict}")
    print("\n(entry 172's rule 1 below reads as a note here: the numpy step moves each network by its "
          "rounding, so no pair's model files are expected equal)")
    E172["main"](LOG, "rule 3")


if __name__ == "__main__":
    main()
