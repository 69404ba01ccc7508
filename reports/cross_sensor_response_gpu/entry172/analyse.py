"""Research log entry 172's reading: `anytip calibrate` with entry 171's code ("old") and this entry's
("new"), alternated (logs/time_calibrate.log). Rule 1: each pair's model files are equal (their SHA-256 in
the log). Rule 2: new over old `wall_s`, paired per (unit, arm, round), the geometric mean with its 95%
t-interval. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry172/analyse.py > \
        reports/cross_sensor_response_gpu/entry172/logs/analyse.log
"""

import runpy
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
E162 = runpy.run_path(str(HERE.parent / "entry162" / "analyse.py"))
timing_line = runpy.run_path(str(HERE.parent / "entry171" / "analyse.py"))["timing_line"]
TARGET_S = 10.0


LOG = HERE / "logs" / "time_calibrate.log"


def calibrations(log: Path = LOG) -> dict[tuple[str, str, str, int], tuple[float, str]]:
    """(code, arm, unit, round) -> (wall_s, model hash), from an alternated timing's log (entry 196's too)."""
    lines = map(timing_line, log.read_text().splitlines())
    return {(t["code"], t["arm"], t["unit"], t["round"]): (float(t["wall_s"]), t["model"])
            for t in lines if t is not None and "model" in t}


def main(log: Path = LOG, rule: str = "rule 2") -> None:
    got = calibrations(log)
    pairs = sorted({k[1:] for k in got if ("old", *k[1:]) in got and ("new", *k[1:]) in got})
    equal = sum(got["old", *p][1] == got["new", *p][1] for p in pairs)
    print(f"rule 1: {equal} of {len(pairs)} pairs' model files equal"
          + ("" if equal == len(pairs) else ": DIFFER"))
    print(f"\n{rule}, new over old wall_s, paired (geometric mean [95% t-interval])")
    print("| arm | pairs | old wall_s | new wall_s | new / old | new under 10 s |")
    print("|---|---|---|---|---|---|")
    for arm in ("alone", "use", "both"):
        mine = [p for p in pairs if arm in ("both", p[0])]
        old = np.array([got["old", *p][0] for p in mine])
        new = np.array([got["new", *p][0] for p in mine])
        mean, lo, hi = (float(np.exp(v)) for v in E162["t_interval"](np.log(new / old)))
        print(f"| {arm} | {len(mine)} | {old.min():.2f}-{old.max():.2f} | {new.min():.2f}-{new.max():.2f} | "
              f"x{mean:.3f} [{lo:.3f}, {hi:.3f}] | {(new < TARGET_S).sum()} of {len(mine)} |")


if __name__ == "__main__":
    main()
