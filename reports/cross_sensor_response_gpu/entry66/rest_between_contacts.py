"""Research log entry 66: do the contact-free rows between presses read the warm-up's drifted rest?

For a registry and its twin simulated with the warm-up at zero (same seed: presses and noise equal), over
every full-protocol run of every unit: the warm-up's offset (registry minus twin, each tared at its run's
start as `anytip.data.arrays` does) and what a re-tare at the rest rows would read besides it (the twin's
tared reading there: the dome's recovery from the last press, noise and the other session conditions).

    python rest_between_contacts.py data/other16 data/other16u [more pairs...] > rest_between_contacts.md
"""

from __future__ import annotations

import sys

import numpy as np

from anytip.data.arrays import contact_mask, rest_reading
from anytip.data.registry import Registry

SINCE_BINS_S = (0.0, 0.15, 0.3, 0.6, 0.9, 1.2)  # time since the last release, s
LONG_S = 1.0  # the decay is read from contact-free stretches at least this long (the patch changes)
FIT_FROM_S = 0.3  # an exponential is fitted to the bins' RMS from here on


def segments(contact: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(starts, releases): row indices where a press starts and the first contact-free row after one."""
    step = np.diff(contact.astype(np.int8))
    return np.flatnonzero(step == 1) + 1, np.flatnonzero(step == -1) + 1


def one_run(reg: Registry, twin: Registry, run_id: str) -> dict[str, np.ndarray]:
    """Per run: the warm-up offset at contact rows and at each press's last rest row (the re-tare's
    removable part), the twin's tared reading at those rest rows (what a re-tare adds), and the twin's
    tared reading at every rest row of the stretches of at least LONG_S after a release, with its time
    since that release."""
    a, b = reg.open_run(run_id), twin.open_run(run_id)
    contact = contact_mask(a)
    if not np.array_equal(contact, contact_mask(b)) or not np.array_equal(a.time, b.time):
        raise SystemExit(f"{run_id}: the twins' presses differ; not the same seed")
    pa = a.pressure - rest_reading(a.pressure, contact, run_id, a.time)
    pb = b.pressure - rest_reading(b.pressure, contact, run_id, b.time)
    warm = pa - pb
    starts, releases = segments(contact)
    last_rest = starts[starts > releases.min()] - 1 if len(releases) else starts[:0]
    since = np.full(len(contact), np.nan)
    for r, nxt in zip(releases, np.append(releases[1:], len(contact)), strict=True):
        free = np.arange(r, nxt)
        free = free[~contact[free]]
        if len(free) and a.time[free[-1]] - a.time[r] >= LONG_S:
            since[free] = a.time[free] - a.time[r]
    rest = ~np.isnan(since)
    return {"warm_contact": warm[contact], "warm_rest": warm[last_rest], "adds": pb[last_rest],
            "since": since[rest], "since_reading": pb[rest], "noise_check": np.diff(warm[contact], axis=0)}


def rms(x: np.ndarray) -> np.ndarray:
    return np.sqrt(np.mean(x.astype(np.float64) ** 2, axis=0))


def report(path: str, twin_path: str) -> str:
    reg, twin = Registry(path, create=False), Registry(twin_path, create=False)
    runs = [r.run_id for r in reg.list_runs(protocol="full")]
    parts = [one_run(reg, twin, rid) for rid in runs]
    cat = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    C = cat["adds"].shape[1]
    lines = [f"## {path} against {twin_path}: {len(runs)} full runs of {len(reg.units())} units, "
             f"{len(cat['adds'])} presses after the first", "",
             "| Pa, RMS | " + " | ".join(f"b{c}" for c in range(C)) + " | all |",
             "|---" * (C + 2) + "|"]

    def row(name: str, v: np.ndarray) -> None:
        lines.append(f"| {name} | " + " | ".join(f"{x:.0f}" for x in rms(v)) + f" | {rms(v.ravel()):.0f} |")

    row("warm-up offset, contact rows", cat["warm_contact"])
    row("warm-up offset at the rest row before a press (a re-tare removes)", cat["warm_rest"])
    row("the rest row's other reading (a re-tare adds)", cat["adds"])
    row("row-to-row change of the warm-up offset, contact rows (twins' noise equal: ~0)", cat["noise_check"])
    lines += ["", f"The rest rows' other reading by time since the last release (the contact-free stretches "
              f"of at least {LONG_S:g} s):", "",
              "| since release, s | rows | RMS Pa, all barometers | b0..b7 |",
              "|---|---|---|---|"]
    mids, levels = [], []
    for lo, hi in zip(SINCE_BINS_S[:-1], SINCE_BINS_S[1:], strict=True):
        m = (cat["since"] >= lo) & (cat["since"] < hi)
        if m.any():
            v = cat["since_reading"][m]
            lines.append(f"| {lo:.2f}-{hi:.2f} | {int(m.sum())} | {rms(v.ravel()):.0f} | "
                         + " ".join(f"{x:.0f}" for x in rms(v)) + " |")
            if lo >= FIT_FROM_S:
                mids.append(float(np.mean(cat["since"][m])))
                levels.append(float(rms(v.ravel())))
    slope, icept = np.polyfit(mids, np.log(levels), 1)
    target = float(rms(cat["warm_rest"].ravel()))
    lines += ["", f"An exponential through the bins from {FIT_FROM_S:g} s: time constant {-1 / slope:.2f} s; "
              f"the reading falls to the removable offset's RMS ({target:.0f} Pa) about "
              f"{(np.log(target) - icept) / slope:.1f} s after a release (an extrapolation)."]
    return "\n".join(lines) + "\n"


def main(argv: list[str]) -> None:
    if len(argv) < 2 or len(argv) % 2:
        raise SystemExit(__doc__)
    print("# Entry 66: the rest between contacts against the warm-up "
          "(generated by rest_between_contacts.py)\n")
    for path, twin in zip(argv[::2], argv[1::2], strict=True):
        print(report(path, twin))


if __name__ == "__main__":
    main(sys.argv[1:])
