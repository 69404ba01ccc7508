"""Research log entry 150: the ceiling of one factor per output (entry 147's diagnostic, chosen on the
held-out units) on other forms of the interval width than the plan's own half-width w: w to the powers 0,
0.5 and 1.5, and w with a fleet floor in quadrature. Reads committed runs only. From the repository root:

    python reports/cross_sensor_response_gpu/entry150/analyse.py
"""

from __future__ import annotations

import runpy
from collections.abc import Callable
from pathlib import Path

import numpy as np

from anytip.uncertainty.fleet_margin import factor_ceiling

G = Path("reports/cross_sensor_response_gpu")
ANALYSE_106 = runpy.run_path(str(G / "entry106/analyse.py"))  # rows_by_unit
ANALYSE_111 = runpy.run_path(str(G / "entry111/analyse.py"))  # fold_rows (its runs keep rows.json)
ANALYSE_108 = runpy.run_path(str(G / "entry108/analyse.py"))  # OUTPUTS
rows_by_unit, OUTPUTS = ANALYSE_106["rows_by_unit"], ANALYSE_108["OUTPUTS"]
DESIGNED, COVER = (
    ("response@designed", "response+use@designed"),
    ("response@cover_informative", "response+use@cover_informative"),
)
ARMS = [
    ("designed, 120 s (entry 147)", [G / f"entry147/at120/fleet88_seed{k}" for k in (0, 1)], DESIGNED),
    (
        "cover_informative, 120 s (entry 147)",
        [G / f"entry147/cover120/fleet88_seed{k}" for k in (0, 1)],
        COVER,
    ),
    ("designed, 600 s (entry 149)", [G / f"entry149/at600/fleet88_seed{k}" for k in (0, 1)], DESIGNED),
    (
        "cover_informative, 64 fresh units (entry 111)",
        [G / f"entry111/fleet88x_seed{k}" for k in (0, 1)],
        COVER,
    ),
]


def floor(s: float) -> Callable[[np.ndarray], np.ndarray]:
    """The own half-width with s times its output's median over the units added in quadrature."""
    return lambda w: np.sqrt(w**2 + (s * np.median(w, axis=0)) ** 2)


FORMS: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "w": lambda w: w,
    "w^0": lambda w: np.ones_like(w),
    "w^0.5": np.sqrt,
    "w^1.5": lambda w: w**1.5,
    "floor 0.5": floor(0.5),
    "floor 1": floor(1.0),
}


def shares(runs: list[Path], method: str) -> dict[str, tuple[float, float]]:
    """Per form, the ceiling's best share in band and its share where none falls below 0.80."""
    if (runs[0] / "rows.json").exists():
        rows = [r for run in runs for r in ANALYSE_111["fold_rows"](run, method).values()]
    else:
        rows = list(rows_by_unit(runs, method).values())

    def field(key: str) -> np.ndarray:
        return np.array([[r[f"{o}_{key}"] for o in OUTPUTS] for r in rows])

    need = [field(f"needed{q}_halfwidth") for q in (80, 85, 95)]
    out = {}
    for name, form in FORMS.items():
        c = factor_ceiling(form(field("halfwidth")), *need)
        out[name] = (c.free_in_band, c.safe_in_band)
    return out


def main() -> None:
    print(
        "ceiling of one factor per output, chosen on the held-out units: best share / share where none is "
        "below 0.80 (change against w where none is below, points)"
    )
    gains = {}
    for label, runs, methods in ARMS:
        for m in methods:
            got = shares(runs, m)
            base = got["w"][1]
            cells = "; ".join(f"{k} {a:.0%}/{b:.0%} ({100 * (b - base):+.0f})" for k, (a, b) in got.items())
            print(f"  {label}, {m}: {cells}")
            gains[(label, m)] = {k: 100 * (b - base) for k, (_, b) in got.items() if k != "w"}
    best = max(max(g.values()) for g in gains.values())
    designed_120 = [g for (label, _), g in gains.items() if label.startswith("designed, 120")]
    noise = [k for k in FORMS if k != "w" and all(g[k] >= 5 for g in designed_120)]
    print(
        f"rule 1: the largest gain of any form over w in any arm: {best:+.1f} points; "
        "forms gaining 5 points or "
        f"more in both designed 120 s arms: {', '.join(noise) or 'none'}"
    )
    print("  reading: " + ("signal" if best <= 2 else "noise" if noise else "between"))


if __name__ == "__main__":
    main()
