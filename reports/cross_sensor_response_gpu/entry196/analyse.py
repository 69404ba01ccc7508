"""Research log entry 196's timing reading: `anytip calibrate` with the code before the numpy step ("old")
and this entry's ("new"), alternated (logs/time_calibrate.log): new over old `wall_s`, paired per (unit, arm,
round), the geometric mean with its 95% t-interval (entry 172's table), then entry 171's threshold per arm on
the new code (the largest work `wall_s x core_gflops` over 10 s, and the median's). From the repository root:

    python reports/cross_sensor_response_gpu/entry196/analyse.py > \\
        reports/cross_sensor_response_gpu/entry196/logs/analyse.log
    python reports/cross_sensor_response_gpu/entry196/analyse.py time_calibrate_b2.log > \\
        reports/cross_sensor_response_gpu/entry196/logs/analyse_b2.log
    python reports/cross_sensor_response_gpu/entry196/analyse.py both > \\
        reports/cross_sensor_response_gpu/entry196/logs/analyse_both.log
"""

import runpy
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
timing_line = runpy.run_path(str(HERE.parent / "entry171" / "analyse.py"))["timing_line"]
E172 = runpy.run_path(str(HERE.parent / "entry172" / "analyse.py"))
LOG = HERE / "logs" / (sys.argv[1] if len(sys.argv) > 1 else "time_calibrate.log")  # (b2): its own log
TARGET_S = 10.0


def lines() -> list[dict[str, str]]:
    """The log's calibrations, parsed."""
    parsed = map(timing_line, LOG.read_text().splitlines())
    return [t for t in parsed if t is not None and "model" in t]


def main() -> None:
    print("(entry 172's rule 1 below reads as a note here: the numpy step moves each network by its "
          "rounding, so no pair's model files are expected equal)")
    E172["main"](LOG, "rule 2")
    print("\nentry 171's threshold on the new code: the work wall_s x core_gflops (GFLOP) over 10 s")
    print("| arm | core_gflops | work | threshold, largest work | threshold, median work |")
    print("|---|---|---|---|---|")
    for arm in ("alone", "use"):
        mine = [t for t in lines() if t["code"] == "new" and t["arm"] == arm]
        gflops = np.array([float(t["core_gflops"]) for t in mine])
        work = np.array([float(t["wall_s"]) for t in mine]) * gflops
        print(f"| {arm} | {gflops.min():.1f}-{gflops.max():.1f} | {work.min():.0f}-{work.max():.0f} | "
              f"{work.max() / TARGET_S:.0f} GFLOP/s | {np.median(work) / TARGET_S:.0f} GFLOP/s |")


def both_parts() -> None:
    """Beside the rules: (b) and (b2) pooled, and their pairs whose two probes read at least 85 GFLOP/s."""
    logs = (HERE / "logs" / "time_calibrate.log", HERE / "logs" / "time_calibrate_b2.log")
    got = {(log.stem, *k): v for log in logs for k, v in E172["calibrations"](log).items()}
    probe = {(log.stem, t["code"], t["arm"], t["unit"], t["round"]): float(t["core_gflops"]) for log in logs
             for t in map(timing_line, log.read_text().splitlines()) if t is not None and "model" in t}
    pairs = sorted({(k[0], *k[2:]) for k in got if k[1] == "new"})
    print("both parts, new over old wall_s, paired (geometric mean [95% t-interval]; new's range)")
    def calm(p: tuple) -> bool:
        return min(probe[p[0], c, *p[1:]] for c in ("old", "new")) >= 85

    for name, keep in (("all", lambda p: True), ("both probes >= 85 GFLOP/s", calm)):
        for arm in ("alone", "use"):
            mine = [p for p in pairs if p[1] == arm and keep(p)]
            old = np.array([got[p[0], "old", *p[1:]][0] for p in mine])
            new = np.array([got[p[0], "new", *p[1:]][0] for p in mine])
            mean, lo, hi = (float(np.exp(v)) for v in E172["E162"]["t_interval"](np.log(new / old)))
            print(f"  {name}, {arm}: {len(mine)} pairs, x{mean:.3f} [{lo:.3f}, {hi:.3f}]; "
                  f"old {old.min():.2f}-{old.max():.2f} s, new {new.min():.2f}-{new.max():.2f} s")


if __name__ == "__main__":
    both_parts() if LOG.name == "both" else main()
