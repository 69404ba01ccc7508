"""Research log entry 151 (run in the variant's worktree, `entry151/variant.patch`): the designed plan of a
budget with each press exchanged, within its neighbourhood, for the place and force level that tells a new
unit's codes most under a response model (criterion v at the code prior's mean, as `cover_informative`
exchanges a unit's recorded presses). Writes the design's presses as `places` JSON, in the design's order.
With `--same-level` (entry 152) a press is exchanged only for candidates of its own force level.

    python reports/cross_sensor_response_gpu/entry151/choose_design.py MODEL SECONDS OUT.json [--same-level]
"""

from __future__ import annotations

import json
import sys

import numpy as np
import torch
from scipy.spatial import cKDTree

from anytip.data.plans import EXCHANGE_PASSES, CodeInformation, RigTiming
from anytip.models.io import load_response
from anytip.sensor.protocols import (
    CELL_DEG,
    PHI_EDGES_DEG,
    THETA_EDGES_DEG,
    build_trajectory,
    design_protocol,
    patch_cells,
)
from anytip.train.response import INFORMATION_ROWS, ResponseFit, code_jacobian, evenly_spaced

# trajectories a candidate's information is averaged over (its point and shear are drawn when pressed)
DRAWS = 4


def press_labels(protocol, orientation: float, rng: np.random.Generator) -> list[np.ndarray]:
    """Each press's contact rows' labels (n, 5): commanded force (N) and angles (rad)."""
    t = build_trajectory(protocol, orientation, rng)
    return [
        np.concatenate([t.force[m], t.angles[m]], 1)
        for m in ((t.press == q) & t.in_contact for q in range(int(t.press.max()) + 1))
    ]


def mean_outer(fit: ResponseFit, labels: np.ndarray) -> np.ndarray:
    """(C, k, k) the mean over label rows (n, 5) of J J^T over the noise variance, J each barometer's
    pressure derivative in its code at the code prior's mean."""
    _, J = code_jacobian(fit.model, torch.tensor(labels, dtype=torch.float32), fit.code_prior.mean)
    return (torch.einsum("rck,rcj->rckj", J, J) / fit.noise_var[:, None, None]).double().mean(0).numpy()


def information(fit: ResponseFit, labels: list[np.ndarray], hz: float, effective_hz: float) -> np.ndarray:
    """(P, C, k, k) each press's information about the codes, as `train.response.press_information`."""
    return np.array([mean_outer(fit, lab[evenly_spaced(len(lab), INFORMATION_ROWS).numpy()])
                     * min(len(lab), len(lab) / hz * effective_hz) for lab in labels])


def summary(places: np.ndarray, layers_n: tuple[float, ...]) -> np.ndarray:
    """(P, 3) a place's normal force level and cell centre (theta, phi), each group over its RMS spread."""
    fz = np.array(layers_n)[places[:, 3]]
    ang = np.stack([THETA_EDGES_DEG[places[:, 1]], PHI_EDGES_DEG[places[:, 2]]], 1) + CELL_DEG / 2
    fz, ang = fz - fz.mean(), ang - ang.mean(0)
    return np.concatenate([(fz / np.sqrt((fz**2).mean()))[:, None], ang / np.sqrt((ang**2).sum(1).mean())], 1)


def main(model: str, seconds: float, out: str, same_level: bool = False) -> None:
    fit = ResponseFit.from_loaded(load_response(model))
    rig = RigTiming()
    design = design_protocol(seconds, rig.move_s, rig.remount_s)
    L = len(design.layers_n)
    mine = np.array(
        [(o, *c, q % L) for o in design.orientations_deg for q, c in enumerate(patch_cells(design, o))],
        dtype=float,
    )
    cand = np.array(
        [
            (o, t, p, lev)
            for o in design.orientations_deg
            for t, p in patch_cells(design.model_copy(update={"patches": 36}), o)
            for lev in range(L)
        ],
        dtype=float,
    )
    cand_places = tuple(tuple(int(v) if i else float(v) for i, v in enumerate(row)) for row in cand)
    probe = design.model_copy(update={"places": cand_places, "patches": 36 * L})
    rng = np.random.default_rng(151)
    per, rows = 0.0, []
    for _ in range(DRAWS):
        labels = [lab for o in design.orientations_deg for lab in press_labels(probe, o, rng)]
        per = per + information(fit, labels, design.sample_rate_hz, rig.effective_hz) / DRAWS
        rows += labels
    every = np.concatenate(rows)
    take = evenly_spaced(len(every), 8192).numpy()
    region = mean_outer(fit, every[take])
    info = CodeInformation(per, fit.code_prior.precision.double().numpy(), region, "v")
    z, zc = summary(mine.astype(int), design.layers_n), summary(cand.astype(int), design.layers_n)
    key = {tuple(r): i for i, r in enumerate(cand.astype(int).tolist())}
    chosen = [key[tuple(r)] for r in mine.astype(int).tolist()]
    cell = np.full(len(cand), -1)
    for o in design.orientations_deg:
        d, c = np.flatnonzero(mine[:, 0] == o), np.flatnonzero(cand[:, 0] == o)
        cell[c] = d[cKDTree(z[d]).query(zc[c])[1]]
    precision = info.prior + per[chosen].sum(0)
    first = value = info.value(precision)
    for _ in range(EXCHANGE_PASSES):
        moved = False
        for j in range(len(chosen)):
            free = np.ones(len(cand), bool)
            free[chosen] = False
            level = cand[:, 3] == mine[j, 3] if same_level else np.ones(len(cand), bool)
            mates = np.flatnonzero(free & (cell == j) & level)
            if not len(mates):
                continue
            trial = precision - per[chosen[j]] + per[mates]
            values = info.values(trial)
            b = int(np.argmax(values))
            if values[b] > value + 1e-9 * max(1.0, abs(value)):
                precision, value, chosen[j], moved = trial[b], float(values[b]), int(mates[b]), True
        if not moved:
            break
    places = [[float(cand[i, 0]), *(int(v) for v in cand[i, 1:])] for i in chosen]
    moved = sum(int(i != key[tuple(r)]) for i, r in zip(chosen, mine.astype(int).tolist(), strict=True))
    levels = np.bincount(cand[chosen, 3].astype(int), minlength=L).tolist()
    Path = __import__("pathlib").Path
    Path(out).write_text(
        json.dumps(
            {
                "name": design.name,
                "model": model,
                "places": places,
                "criterion_v": {"design": -first, "exchanged": -value},
                "exchanged_presses": moved,
                "presses_per_level": levels,
            },
            indent=1,
        )
        + "\n"
    )
    print(
        f"{design.name} from {model}: {len(chosen)} presses, {moved} exchanged; remaining variance (v) "
        f"{-first:.3f} -> {-value:.3f} (x{value / first:.3f}); presses per force level {levels}"
    )


if __name__ == "__main__":
    main(sys.argv[1], float(sys.argv[2]), sys.argv[3], "--same-level" in sys.argv[4:])
