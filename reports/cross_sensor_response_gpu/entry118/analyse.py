"""Research log entry 118: today's recipe at severity 0.5, 1 and 2, read as pre-registered.

For each rescoring in entry118/ (`rescore.sh NAME`):
1. the gate: its `per_unit` rows (the run's saved references scored again on the rebuilt registry, where
   the run saved them) against the run's committed ones, every RMSE field;
2. per budget and method (`response` and `response+use` on `cover_informative` plans): force and angle ratio
   to each held-out unit's reference, mean over units [95% bootstrap interval over units]
   (`report.cross_sensor.summary`, as every report computes it), and the interval target's share in band
   and count below 0.80;
3. paired per unit against the run's committed `response@cover` row of the same budget: the geometric mean of
   the force RMSE ratio [95% bootstrap interval over units].

    python reports/cross_sensor_response_gpu/entry118/analyse.py
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import summary

G = Path("reports/cross_sensor_response_gpu")
RUNS = {"severity0.5": "reports/cross_sensor_response_severity/severity0.5",
        "fleet24_seed1": "reports/cross_sensor_response_start/fleet24_seed1",
        "severity2": "reports/cross_sensor_response_severity/severity2",
        "severity2_extra2": "reports/cross_sensor_response_severity/severity2_extra2"}
SEVERITY = {"severity0.5": "0.5", "fleet24_seed1": "1", "severity2": "2", "severity2_extra2": "2, extra at 2"}
METHODS = ("response@cover_informative", "response+use@cover_informative")
OUTPUTS = ("fx", "fy", "fz", "theta", "phi")
RMSE = [f"{o}_rmse" for o in OUTPUTS] + ["force_rmse_n", "angle_rmse_rad"]


def rows_of(run: Path) -> list[dict[str, Any]]:
    return json.loads((run / "metrics.json").read_text())["results"]


def gate(new: list[dict[str, Any]], old: list[dict[str, Any]], saved: bool) -> str:
    """Rule 1: the rescoring's per_unit rows against the run's; `saved`: whether the run saved its
    references (else the rescoring copies its rows, and there is nothing to check)."""
    if not saved:
        return "none (the run saved no references; its per_unit rows are copied)"
    a = {r["unit"]: r for r in new if r["method"] == "per_unit"}
    b = {r["unit"]: r for r in old if r["method"] == "per_unit"}
    if set(a) != set(b):
        return "FAILS: other units"
    worst = max(abs(a[u][k] - b[u][k]) for u in a for k in RMSE)
    return f"{len(a)} references, largest difference {worst:.3g}" + (" (equal)" if worst == 0 else "")


def bootstrap_gmean(x: np.ndarray, n: int = 10_000, seed: int = 0) -> tuple[float, float, float]:
    """Geometric mean of x (units,) with a 95% bootstrap interval over units."""
    rng = np.random.default_rng(seed)
    logs = np.log(x)
    means = logs[rng.integers(0, len(x), (n, len(x)))].mean(1)
    return float(np.exp(logs.mean())), *np.exp(np.quantile(means, [0.025, 0.975]))


def paired_force(new: list[dict[str, Any]], old: list[dict[str, Any]], method: str, budget: float,
                 against: str | None = None) -> tuple[float, float, float]:
    """Each held-out unit's force RMSE of `method` at `budget` in `new` over its row of `against` (default the
    same method) in `old`: geometric mean over units with a 95% bootstrap interval."""
    before = {r["unit"]: r for r in old if r["method"] == (against or method) and r["budget_s"] == budget}
    got = [r for r in new if r["method"] == method and r.get("budget_s") == budget]
    return bootstrap_gmean(np.array([r["force_rmse_n"] / before[r["unit"]]["force_rmse_n"] for r in got]))


def intervals(rows: list[dict[str, Any]]) -> str:
    """The interval target on these rows: the fleet factor times its margin as `anytip calibrate` applies
    them (`<output>_margin_coverage`), or the fleet factor's alone where rows predate margins; share in
    [0.85, 0.95] and count below 0.80."""
    for kind in ("margin", "fleet"):
        cov = np.array([[r[f"{o}_{kind}_coverage"] for o in OUTPUTS] for r in rows
                        if f"fx_{kind}_coverage" in r])
        if cov.size:
            band = ((cov >= 0.85) & (cov <= 0.95)).mean()
            return (f"{kind}: {band:.0%} of {cov.size} in band, {(cov < 0.80).sum()} below 0.80 "
                    f"(lowest {cov.min():.3f})")
    return "no intervals"


def line_of(rows: list[dict[str, Any]], method: str, budget: float) -> str:
    """Force and angle ratio of `method` at `budget`: mean over units [95% interval over units]."""
    line = next(s for s in summary(rows) if s["method"] == method and s["budget"] == budget)
    return " / ".join(f"{line[f'{m}_unit'][0]:.3f}x [{line[f'{m}_unit'][1]:.2f}, {line[f'{m}_unit'][2]:.2f}]"
                      for m in ("force", "angle")) + f" ({line['units']} units)"


def main() -> None:
    for name, source in RUNS.items():
        out = G / "entry118" / name
        if not (out / "metrics.json").is_file():
            print(f"{name}: not run")
            continue
        new, old = rows_of(out), rows_of(Path(source))
        print(f"== {name} (severity {SEVERITY[name]}): gate: "
              f"{gate(new, old, (Path(source) / 'models' / 'per_unit_seed1_lr0').is_dir())}")
        for budget in (120.0, 600.0):
            before = {r["unit"]: r for r in old
                      if r["method"] == "response@cover" and r["budget_s"] == budget}
            for method in METHODS:
                got = [r for r in new if r["method"] == method and r.get("budget_s") == budget]
                if not got:
                    continue
                s = line_of(new, method, budget)
                g, lo, hi = paired_force(new, old, method, budget, "response@cover")
                print(f"   {budget:g} s {method}: {s}; against the run's "
                      f"response@cover x{g:.3f} [{lo:.3f}, {hi:.3f}]; intervals {intervals(got)}")
            print(f"   {budget:g} s the run's response@cover: {line_of(old, 'response@cover', budget)}; "
                  f"intervals {intervals(list(before.values()))}")


if __name__ == "__main__":
    main()
