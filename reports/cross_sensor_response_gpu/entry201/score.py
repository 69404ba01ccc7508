"""Research log entry 201's reading: the 90% intervals `anytip calibrate` reported for entry 201's 64 fresh
units (build/entry201/P-FOLD/UNIT, `run.sh`), on each unit's full runs, which no calibration read: rule 1
(the gate), rule 2 (the target on the 320 unit-outputs) and, beside them, the same networks' own
half-widths times the factor of the fold's run for codes fitted with 600 s of use (U, the default before
entry 198) and for the plan alone (A, before entry 199's pooling).

    python reports/cross_sensor_response_gpu/entry201/score.py > \\
        reports/cross_sensor_response_gpu/entry201/logs/score.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

from anytip.data.registry import Registry
from anytip.uncertainty.conformal import coverage, interval

HERE = Path(__file__).parent
E198 = runpy.run_path(str(HERE.parent / "entry198" / "analyse.py"))
PAIRS = runpy.run_path(str(HERE / "units.py"))["PAIRS"]
REGISTRIES = {"f": "data/test201d", "o": "data/test201o"}
GROUPS = (("default fingertip, 32 fresh (SIM44)", "f"), ("other elastomer, 32 fresh (SIM26)", "o"),
          ("all 64", "fo"))


def scored(fold: str, unit: str, registry: Registry) -> tuple[dict[str, np.ndarray], bool]:
    """Per arm (P as reported, U, A), the coverage (D,) of the unit's network on its full runs; the gate."""
    cal = Path("build/entry201") / f"P-{fold}" / unit
    rec, meta, names, own, pred, target = E198["on_full_runs"](cal, registry)
    ours = rec["intervals"]
    factors = E198["factors"](meta["response_model"], rec["unlabeled_seconds"])[0]
    half = np.array([ours["halfwidth"][n] for n in names])
    out = {"P": coverage(*interval(pred, half), target)}
    out |= {arm: coverage(*interval(pred, own * factors[arm]), target) for arm in ("U", "A")}
    said = " ".join(rec["notes"])
    gate = ("intervals: the plan alone's fleet factor" in said and "(--factor-from" in said
            and rec["check"]["rows"] == len(pred)
            and np.allclose(out["P"], [ours["coverage_on_other_runs"][n] for n in names], atol=1e-6))
    return out, gate


def main() -> None:
    got = {(f, u): scored(f, u, Registry(REGISTRIES[f[0]])) for f, u in PAIRS}
    print(f"rule 1: {sum(g for _, g in got.values())} of {len(got)} calibrations pass the gate")
    for name, keep in GROUPS:
        print(f"## {name}")
        for arm, what in (("P", "as reported (pooled plan-alone factor)"), ("U", "the fold's use factor"),
                          ("A", "the fold's plan-alone factor")):
            cov = np.array([c[arm] for (f, _), (c, _) in got.items() if f[0] in keep])
            print(f"  {arm}, {what}: {E198['summary'](cov)}")


if __name__ == "__main__":
    main()
