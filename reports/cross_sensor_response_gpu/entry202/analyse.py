"""Research log entry 202's reading: the shipped path's intervals with a fleet factor learnt on units
calibrated through the shipped path itself (C: `uncertainty.fleet_margin.pooled_factor` over learners
whose own half-widths are their calibrations' recorded ones and whose needed half-widths come from their
full runs), against the pooled benchmark factor the path takes today (P, entry 199). Decision (rule 2): on
entry 191's 64 validation units, each elastomer's 32 split into even and odd units, C learnt on one half
scores the other. Read after (rule 3): entry 201's 64 fresh units under C learnt on all 32 validation
units of their elastomer, beside P as reported.

    python reports/cross_sensor_response_gpu/entry202/analyse.py > \\
        reports/cross_sensor_response_gpu/entry202/logs/analyse.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

from anytip.data.registry import Registry
from anytip.uncertainty.conformal import coverage, interval, needed_halfwidths, residual_halfwidth
from anytip.uncertainty.fleet_margin import Learner, pooled_factor

HERE = Path(__file__).parent
E198 = runpy.run_path(str(HERE.parent / "entry198" / "analyse.py"))
E199 = runpy.run_path(str(HERE.parent / "entry199" / "analyse.py"))
LEVEL, EDGES = 0.9, (0.80, 0.85, 0.95)
VALIDATION = {"f": ("build/entry191/H-f*/SIM41-*", "data/val191d"), "o": ("build/entry191/H-o*/SIM24-*",
                                                                         "data/val191o")}
FRESH = {"f": ("build/entry201/P-f*/SIM44-*", "data/test201d"), "o": ("build/entry201/P-o*/SIM26-*",
                                                                     "data/test201o")}


class Unit:
    """One calibration read on its unit's full runs (entry 198's `FullRuns`, `read`), its reported
    half-widths (D,) and its `Learner`."""

    def __init__(self, calibration: Path, registry: Registry):
        self.read = E198["on_full_runs"](calibration, registry)
        self.pred, self.target, self.own = self.read.pred, self.read.target, self.read.own
        self.reported = np.array([self.read.rec["intervals"]["halfwidth"][n] for n in self.read.names])
        miss = self.pred - self.target
        self.learner = Learner(self.own, residual_halfwidth(miss, LEVEL), *needed_halfwidths(miss, EDGES))

    def covered(self, half: np.ndarray) -> np.ndarray:
        return coverage(*interval(self.pred, half), self.target)


def read(where: tuple[str, str]) -> list[Unit]:
    registry = Registry(where[1])
    return [Unit(p, registry) for p in sorted(Path().glob(where[0])) if p.is_dir()]


def learnt(learners: list[Learner]) -> np.ndarray:
    """C's factor (D,), its margin included."""
    factor, choice = pooled_factor(learners)
    return factor * choice.margin


def main() -> None:
    rows: dict[str, dict[str, list[np.ndarray]]] = {}
    for kind in "fo":
        val = read(VALIDATION[kind])
        halves = (val[0::2], val[1::2])
        for k, half in enumerate(halves):
            factor = learnt([u.learner for u in halves[1 - k]])
            for u in half:
                p = E199["arms"](u.read)[0]["P"]
                rows.setdefault(f"validation {kind}", {}).setdefault("P", []).append(p)
                rows[f"validation {kind}"].setdefault("C", []).append(u.covered(u.own * factor))
        factor = learnt([u.learner for u in val])
        print(f"C's factor for {kind} from all 32 validation units: {np.round(factor, 3).tolist()}")
        for u in read(FRESH[kind]):
            rows.setdefault(f"fresh {kind}", {}).setdefault("P", []).append(u.covered(u.reported))
            rows[f"fresh {kind}"].setdefault("C", []).append(u.covered(u.own * factor))
    for group in ("validation", "fresh"):
        for keep in ("f", "o", "fo"):
            name = f"{group} {keep}"
            print(f"## {name} ({'rule 2' if group == 'validation' else 'rule 3, read after'})")
            for arm in ("P", "C"):
                cov = np.array([c for k in keep for c in rows[f"{group} {k}"][arm]])
                print(f"  {arm}: {E198['summary'](cov)}")


if __name__ == "__main__":
    main()
