"""How a run without `in_contact` finds its contacts from its force reading, against the flag its
simulator wrote: per protocol, the flagged presses cut into more than one found contact, those missed,
found contacts that join flagged presses, found contacts outside every flagged row, and the found rows
outside the flag as a share of the flag's. Four rules: one threshold at CONTACT_FORCE_N on the raw
reading (the rule before `force_contact`), the same on the reading taken from its rest median, that with
hysteresis down to CONTACT_RELEASE_N, and `force_contact` (the two thresholds scaled up to the sensor's
noise at rest where it is larger).

    python scripts/contact_from_force.py data/fleet88p full,short,plan120,plan60 60
"""

from __future__ import annotations

import sys
from collections.abc import Callable

import numpy as np

from anytip.data.arrays import CONTACT_FORCE_N, CONTACT_RELEASE_N, force_contact, force_rest, hysteresis
from anytip.data.registry import Registry


def one_threshold(tared: bool) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    """|F| >= CONTACT_FORCE_N of a reading (n, 3) N at time (n,) s, from its rest median where `tared`."""
    def rule(force: np.ndarray, time: np.ndarray) -> np.ndarray:
        zero = force_rest(force, time)[0] if tared else 0.0
        return np.linalg.norm(force - zero, axis=1) >= CONTACT_FORCE_N
    return rule


def fixed_hysteresis(force: np.ndarray, time: np.ndarray) -> np.ndarray:
    """`force_contact` without its noise scaling: from the rest median, on at CONTACT_FORCE_N, off
    below CONTACT_RELEASE_N."""
    magnitude = np.linalg.norm(force - force_rest(force, time)[0], axis=1)
    return hysteresis(magnitude, CONTACT_FORCE_N, CONTACT_RELEASE_N)


def segments(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(starts, ends) of the runs of True in `mask` (n,), ends exclusive."""
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return np.flatnonzero(d == 1), np.flatnonzero(d == -1)


def compare(flag: np.ndarray, found: np.ndarray) -> np.ndarray:
    """(flagged presses, split, missed, found joining presses, found outside the flag, found rows outside,
    flag rows) of one run's flag (n,) bool and found contacts (n,) bool."""
    fs, fe = segments(found)
    cs, ce = segments(flag)
    # found segments overlapping each flagged press: those starting before its end, less those ending
    # by its start
    touching = np.searchsorted(fs, ce) - np.searchsorted(fe, cs, side="right")
    inside = np.cumsum(np.concatenate([[0], flag]))
    outside = int(np.count_nonzero(inside[fe] - inside[fs] == 0))
    # flagged presses each found segment overlaps, the same way round
    spans = np.searchsorted(cs, fe) - np.searchsorted(ce, fs, side="right")
    return np.array([len(cs), np.count_nonzero(touching > 1), np.count_nonzero(touching == 0),
                     np.count_nonzero(spans > 1), outside, np.count_nonzero(found & ~flag),
                     np.count_nonzero(flag)])


def main(root: str, protocols: str, per_protocol: int) -> None:
    registry = Registry(root)
    rules = {"one threshold, raw": one_threshold(False), "one threshold, from rest": one_threshold(True),
             "two fixed thresholds, from rest": fixed_hysteresis, "force_contact": force_contact}
    print("| protocol | runs | rule | flagged presses | split | missed | found joining presses | "
          "found outside the flag | found rows outside the flag |")
    print("|---|---|---|---|---|---|---|---|---|")
    for protocol in protocols.split(","):
        records = registry.list_runs(protocol=protocol)[:per_protocol]
        runs = [registry.open_run(r.run_id) for r in records]
        for name, rule in rules.items():
            total = sum(compare(r.in_contact.astype(bool), rule(r.force, r.time)) for r in runs)
            print(f"| {protocol} | {len(runs)} | {name} | " + " | ".join(str(v) for v in total[:5]) +
                  f" | {total[5] / max(total[6], 1):.4f} |")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]))
