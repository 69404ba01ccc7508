"""Research log entry 176: can a unit in ordinary use find its own contacts from its pressures alone?

The benchmark and `anytip calibrate --ordinary-use` read ordinary use as whole presses of a unit's recorded
contact rows (`in_contact`). A deployed unit has no such flag: it would find its contacts from its
pressures. This scores two detectors that read pressures alone against the simulator's `in_contact`, on
every full run (602 s, three orientations, the warm-up from power-up, as ordinary use after mounting) of a
registry's units:

- `fixed`: a row is in contact where some barometer lies more than a threshold from the run's rest
  reading (the mean of its first 0.5 s, which the format guarantees at rest);
- `tracking`: the same against a baseline that follows the rest: the pressures of the rows `fixed` finds
  at rest, interpolated over time and smoothed by a running median of 2 s (on a 0.05 s grid), then the
  same threshold.

Thresholds: 6 times each barometer's own rest noise (the standard deviation of its first 0.5 s; for
Gaussian noise a false alarm about once in 1e9 rows per barometer), and 100, 200 and 400 Pa. Per detector
and threshold, over all rows: the share of contact rows found (recall), of them at |F| >= 1 N, and the
share of found rows that are not contact rows (false share); and the found contact segments per true press.
Prints one markdown table (and the rest noise and the rest baseline's largest departure for scale); a third
argument names another protocol than `full` (research log entry 177):

    python reports/cross_sensor_response_gpu/entry176/contact_from_pressure.py data/fleet88 SIM40 \
        > reports/cross_sensor_response_gpu/entry176/logs/contact.log
"""

from __future__ import annotations

import sys
from collections import defaultdict

import numpy as np
from scipy.ndimage import median_filter

from anytip.data.registry import Registry

REST_S, MEDIAN_S, STEP_S, NOISE_K = 0.5, 2.0, 0.05, 6.0
LEVELS_PA = (100.0, 200.0, 400.0)
FIRM_N = 1.0


def segments(mask: np.ndarray) -> int:
    """The number of contiguous True stretches of mask (n,)."""
    return int(np.count_nonzero(np.diff(mask.astype(np.int8), prepend=0) == 1))


def tracking_baseline(time: np.ndarray, pressure: np.ndarray, rest: np.ndarray) -> np.ndarray:
    """(n, C): the pressures of the rows `rest` (n,) bool, interpolated over `time` and smoothed by a
    running median of MEDIAN_S seconds (taken on a grid of STEP_S, then interpolated back)."""
    grid = np.arange(time[0], time[-1] + STEP_S, STEP_S)
    width = max(1, int(round(MEDIAN_S / STEP_S)))
    out = np.empty_like(pressure)
    for c in range(pressure.shape[1]):
        coarse = median_filter(np.interp(grid, time[rest], pressure[rest, c]), size=width, mode="nearest")
        out[:, c] = np.interp(time, grid, coarse)
    return out


def score(found: np.ndarray, contact: np.ndarray, firm: np.ndarray) -> np.ndarray:
    """Counts: found contact rows, contact rows, found firm rows, firm rows, found rows, found segments,
    true presses."""
    return np.array([np.count_nonzero(found & contact), np.count_nonzero(contact),
                     np.count_nonzero(found & firm), np.count_nonzero(firm), np.count_nonzero(found),
                     segments(found), segments(contact)], float)


def run_scores(run) -> tuple[dict[tuple[str, str], np.ndarray], float, float]:  # noqa: ANN001 - a CalibrationRun
    """Per (detector, threshold) the counts of `score` for one run; its median rest noise (Pa) and the
    largest drift of its tracked baseline from the rest reading (Pa)."""
    t, p = run.time, run.pressure.astype(np.float64)
    contact, firm = run.in_contact.astype(bool), np.linalg.norm(run.force, axis=1) >= FIRM_N
    first = t - t[0] < REST_S
    rest, noise = p[first].mean(0), p[first].std(0)
    out = {}
    for label, threshold in [("6 sigma", NOISE_K * noise), *((f"{v:g} Pa", v) for v in LEVELS_PA)]:
        fixed = (np.abs(p - rest) > threshold).any(1)
        base = tracking_baseline(t, p, ~fixed)
        tracked = (np.abs(p - base) > threshold).any(1)
        out["fixed", label] = score(fixed, contact, firm)
        out["tracking", label] = score(tracked, contact, firm)
    drift = float(np.abs(tracking_baseline(t, p, ~contact) - rest).max())
    return out, float(np.median(noise)), drift


def main(root: str, prefix: str, protocol: str = "full") -> None:
    registry = Registry(root)
    runs = [r for r in registry.list_runs() if r.protocol == protocol and r.unit.startswith(prefix)]
    totals: dict[tuple[str, str], np.ndarray] = defaultdict(lambda: np.zeros(7))
    noises, drifts = [], []
    for record in runs:
        scores, noise, drift = run_scores(registry.open_run(record.run_id))
        for key, counts in scores.items():
            totals[key] += counts
        noises.append(noise)
        drifts.append(drift)
    units = len({r.unit for r in runs})
    print(f"{len(runs)} {protocol} runs of {units} units ({prefix}*) in {root}; rest noise per barometer "
          f"(median per run) {np.min(noises):.1f}-{np.max(noises):.1f} Pa; the rest baseline's largest drift "
          f"from the run's first rest reading {np.min(drifts):.0f}-{np.max(drifts):.0f} Pa (median "
          f"{np.median(drifts):.0f})\n")
    print("| detector | threshold | contact rows found | of them at abs(F) >= 1 N "
          "| found rows not in contact | found segments per true press |")
    print("|---|---|---|---|---|---|")
    for (detector, label), c in totals.items():
        print(f"| {detector} | {label} | {c[0] / c[1]:.4f} | {c[2] / c[3]:.4f} | {(c[4] - c[0]) / c[4]:.4f} "
              f"| {c[5] / c[6]:.3f} |")


if __name__ == "__main__":
    main(*sys.argv[1:4])
