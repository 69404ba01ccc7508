"""Fault detection of the uncertainty pipeline: simulated faults on held-out rows, foreign
units (stronger casting defects, another sensor model), the rest-drift detector, and the
AUROC of every "untrustworthy" signal per row and per window.
"""

from __future__ import annotations

import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from anytip.data.arrays import FleetArrays, has_patch_grid, load_arrays
from anytip.data.faults import MissingData, RunStream, baseline_drift, fault_suite, rest_rows, run_streams
from anytip.data.registry import Registry
from anytip.data.seeds import FAULT_ROWS, FOREIGN_UNITS, stream_seed
from anytip.data.simulated import simulate_into
from anytip.errors import AnytipError
from anytip.pipelines.common import Context
from anytip.pipelines.uncertainty_options import Options
from anytip.sensor.fleet import FleetConfig, NominalParams, SpreadParams
from anytip.uncertainty.detect import (
    InputNovelty,
    KnnNovelty,
    auroc,
    contiguous_windows,
    flatline,
    rest_offset,
    unit_signals,
    window_means,
)
from anytip.uncertainty.ensembles import EnsembleFit, predict_members
from anytip.uncertainty.rest_drift import RestDriftDetector
from anytip.uncertainty.split import UQSplit


def foreign_fleets(spec_fleet: FleetConfig) -> dict[str, FleetConfig]:
    """Units no training unit resembles: stronger casting defects (3x direction defects,
    4x bubble chance, stronger voids), and another sensor model (stiffer rubber, weaker
    coupling, larger indenter, stronger direction coupling)."""
    s = spec_fleet.spread
    strong = SpreadParams(**{**s.model_dump(), "direction_defect_sigma": 3 * s.direction_defect_sigma,
                             "bubble_probability": min(1.0, 4 * s.bubble_probability),
                             "bubble_strength_max": 0.9})
    n = spec_fleet.nominal
    other = NominalParams(**{**n.model_dump(), "modulus_pa": 2 * n.modulus_pa, "coupling_gain": 0.8,
                             "indenter_radius_m": 1.2 * n.indenter_radius_m, "direction_coupling": 0.5})
    return {"strong_defects_unit": spec_fleet.model_copy(update={"spread": strong}),
            "other_sensor_model": spec_fleet.model_copy(update={"sensor_model": "fingertip-other",
                                                                "nominal": other})}


def foreign_pressures(ctx: Context, opts: Options, seed: int, root: Path) -> dict[str, np.ndarray]:
    """Tared pressures (n, C) of simulated foreign units, read back through registries
    under `root` (the same path as any other data; the configs are in foreign_fleets)."""
    out = {}
    for k, (name, cfg) in enumerate(foreign_fleets(ctx.spec.fleet).items()):
        reg = Registry(root / f"{name}_seed{seed}")
        simulate_into(reg, cfg, opts.foreign_units, seed=stream_seed(FOREIGN_UNITS, seed, k),
                      protocols=("short",))
        out[name] = load_arrays(reg, reg.list_runs()).pressure
    return out


def fault_rows(ctx: Context, arrays: FleetArrays, fit: EnsembleFit, split: UQSplit, opts: Options,
               seed: int, keys: Sequence[str] = ("force_rmse_n", "angle_rmse_rad")) -> list[dict[str, Any]]:
    """AUROC of every signal for every fault on every unit, per row and per window: clean
    test rows against the same rows with the fault injected (or a foreign unit's rows
    through this unit's model). Rows are whole windows of consecutive test rows."""
    fingertip = has_patch_grid(arrays.layout)  # the foreign units are simulated fingertips
    if opts.foreign_units and not fingertip:
        note = (f"foreign-unit faults skipped: the simulator's foreign units are fingertips, not "
                f"{ctx.provenance.get('sensor_model')!r} units")
        if note not in ctx.provenance.setdefault("skipped", []):
            ctx.provenance["skipped"].append(note)
    with tempfile.TemporaryDirectory() as tmp:
        foreign = foreign_pressures(ctx, opts, seed, Path(tmp)) if opts.foreign_units and fingertip else {}
    rows = []
    for u, unit in enumerate(split.data.unit_ids):
        rng = np.random.default_rng(stream_seed(FAULT_ROWS, seed, u))
        pick = contiguous_windows(len(split.X_test[u]), max(opts.windows), opts.max_detect_rows, rng)
        x = split.X_test[u][pick]
        novelty = (InputNovelty.fit(split.X_fit[u]), KnnNovelty.fit(split.X_fit[u], seed=seed))
        ch = int(rng.integers(x.shape[1]))
        faults = fault_suite(x, split.X_fit[u], rng, opts.drift_pa, ch) | {
            k: v[contiguous_windows(len(v), max(opts.windows), opts.max_detect_rows, rng)]
            for k, v in foreign.items()}
        clean = _signals(fit, u, x, novelty)
        base = {"unit": unit, "seed": seed, "calib_samples": int(split.data.n_train[u]),
                **dict.fromkeys(keys)}  # detection rows score no target
        for fault, xf in faults.items():
            bad = _signals(fit, u, xf, novelty)
            changed = (xf != x).any(1) if fault == "saturation" else slice(None)
            for signal in clean:
                for w in (1, *opts.windows):
                    c = window_means(clean[signal][changed], w)
                    b = window_means(bad[signal][changed], w)
                    if len(b) == 0 or (fault == "saturation" and w > 1):
                        continue
                    rows.append({**base, "method": f"detect:{signal}", "fault": fault, "window": w,
                                 "fault_rows": len(xf), "auroc": auroc(c, b)})
            if fault != "saturation":
                rows.append({**base, "method": "detect:flatline", "fault": fault, "window": opts.windows[0],
                             "fault_rows": len(xf), "auroc": auroc(flatline(x, opts.windows[0]),
                                                                   flatline(xf, opts.windows[0]))})
        rows += rest_drift_rows(ctx, arrays, u, opts, rng, base)
        try:
            rows += rest_model_rows(ctx, arrays, split, u, pick, ch, opts, base)
        except MissingData as e:  # temperature is optional in the format
            skipped = ctx.provenance.setdefault("skipped", [])
            line = f"rest-drift detector (`detect:rest_drift`) skipped: {e}; it needs barometer temperatures"
            if line not in skipped:
                skipped.append(line)
    return rows


def rest_drift_rows(ctx: Context, arrays: FleetArrays, u: int, opts: Options,
                    rng: np.random.Generator, base: dict[str, Any]) -> list[dict[str, Any]]:
    """Baseline drift judged where a deployed unit sees it best: its contact-free rows
    between touches (never used for training or tare), clean against offset."""
    rest = rest_rows(ctx.registry, [r for r in arrays.runs if r.unit == arrays.units[u]])
    if len(rest) < 2 * opts.windows[0]:
        return []
    ch = np.array([int(rng.integers(rest.shape[1]))])
    clean, rows = rest_offset(rest, opts.windows[0]), []
    for a in opts.drift_pa:
        for name, chans in ((f"drift_all_{a / 1000:g}kPa", None), (f"drift_one_{a / 1000:g}kPa", ch)):
            bad = rest_offset(baseline_drift(rest, a, chans), opts.windows[0])
            rows.append({**base, "method": "detect:rest_offset", "fault": name, "window": opts.windows[0],
                         "fault_rows": len(rest), "auroc": auroc(clean, bad)})
    return rows


def unit_streams(ctx: Context, arrays: FleetArrays, u: int, test_idx: np.ndarray
                 ) -> tuple[list[RunStream], list[np.ndarray], Any]:
    """Unit u's full recorded streams, a mask per stream of the rows that belong to no
    test patch (contact rows of training or calibration patches, and the contact-free rows
    after them), and a map from test-row indices of the arrays to (stream, row)."""
    run_ids = [k for k, r in enumerate(arrays.runs) if r.unit == arrays.units[u]]
    streams = run_streams(ctx.registry, [arrays.runs[k] for k in run_ids], run_ids)
    test_patches = np.unique(arrays.patch[test_idx])
    non_test, contact_rows, arr_rows = [], [], []
    for st in streams:
        rows_c, rows_a = np.flatnonzero(st.contact), np.flatnonzero(arrays.run == st.run)
        if len(rows_c) != len(rows_a):
            raise AnytipError(f"run {arrays.runs[st.run].run_id}: {len(rows_c)} contact rows in the "
                              f"stream, {len(rows_a)} loaded")
        last = np.searchsorted(rows_c, np.arange(len(st.contact)), side="right") - 1  # latest press
        patch = np.where(last >= 0, arrays.patch[rows_a][np.maximum(last, 0)], -1)
        non_test.append((patch >= 0) & ~np.isin(patch, test_patches))
        contact_rows.append(rows_c)
        arr_rows.append(rows_a)
    where = {st.run: i for i, st in enumerate(streams)}

    def locate(idx: np.ndarray) -> list[tuple[int, int]]:
        out = []
        for g in idx:
            i = where[int(arrays.run[g])]
            out.append((i, int(contact_rows[i][np.searchsorted(arr_rows[i], g)])))
        return out

    return streams, non_test, locate


def longest_contact(contact: np.ndarray) -> int:
    """Rows of the longest run of consecutive True in `contact` (n,) bool."""
    edges = np.flatnonzero(np.diff(np.r_[0, contact.astype(np.int8), 0]))
    return int((edges[1::2] - edges[::2]).max(initial=0))


def rest_model_rows(ctx: Context, arrays: FleetArrays, split: UQSplit, u: int, pick: np.ndarray, ch: int,
                    opts: Options, base: dict[str, Any]) -> list[dict[str, Any]]:
    """AUROC of the rest-drift detector (`anytip.uncertainty.rest_drift`), two ways; distances
    are in units of the detector's limit (1 is where it flags).

    `detect:rest_drift`: fitted on every run of the unit, on the rows of training and
    calibration patches only (and the contact-free rows after them), so its statistics come
    from the same power-ups as the scored rows; drifted from tare on; the same test windows
    as the other signals. `detect:rest_drift:other_runs`: for each run, fitted on the unit's
    other runs (other power-ups), its clean mean re-learnt on the run's own first
    `rest_reference_rows` after tare; the drift starts after them, and only the windows that
    start once the drift has settled in the state are scored."""
    streams, non_test, locate = unit_streams(ctx, arrays, u, split.test_idx[u])
    block = opts.rest_block_rows or 2 * max(longest_contact(st.contact) for st in streams)
    pairs = [(st.pressure, st.temperature) for st in streams]
    starts = [int(np.argmax(st.contact)) + 1 for st in streams]  # watched after the first contact
    rest = [n & ~st.contact & st.after_tare for n, st in zip(non_test, streams, strict=True)]
    watch = [n & st.after_tare for n, st in zip(non_test, streams, strict=True)]
    at = locate(split.test_idx[u][pick])
    same = RestDriftDetector.fit(pairs, rest, watch, block, starts)
    rows = _drift_auroc(streams, [same] * len(streams), starts, [0] * len(streams), at, ch, opts,
                        {**base, "method": "detect:rest_drift", "block_rows": block})
    if len(streams) < 2:
        return rows
    onsets = [k + opts.rest_reference_rows for k in starts]
    dets = []
    for i in range(len(streams)):
        other = [j for j in range(len(streams)) if j != i]
        det = RestDriftDetector.fit([pairs[j] for j in other], [rest[j] for j in other],
                                    [watch[j] for j in other], block, [starts[j] for j in other])
        n = np.arange(len(streams[i].contact))
        dets.append(det.rereferenced(pairs[i], starts[i], non_test[i] & (n >= starts[i] + 2 * block)
                                     & (n < onsets[i])))
    w = max(opts.windows)
    settled = np.array([r >= onsets[i] + 4 * block for i, r in at])
    if len(settled) % w == 0:
        settled = settled.reshape(-1, w).all(1).repeat(w)
    kept = [x for x, k in zip(at, settled, strict=True) if k]
    if kept:
        rows += _drift_auroc(streams, dets, starts, onsets, kept, ch, opts,
                             {**base, "method": "detect:rest_drift:other_runs", "block_rows": block})
    return rows


def _drift_auroc(streams: list[RunStream], dets: list[RestDriftDetector], starts: list[int],
                 onsets: list[int], at: list[tuple[int, int]], ch: int, opts: Options,
                 base: dict[str, Any]) -> list[dict[str, Any]]:
    """Clean against drifted streams, read at the (stream, row) positions `at`."""

    def read(sts: list[RunStream]) -> np.ndarray:
        sig = [d((st.pressure, st.temperature), k) / d.limit
               for d, st, k in zip(dets, sts, starts, strict=True)]
        return np.array([sig[i][r] for i, r in at])

    clean, rows = read(streams), []
    for a in opts.drift_pa:
        for name, chans in ((f"drift_all_{a / 1000:g}kPa", None), (f"drift_one_{a / 1000:g}kPa", [ch])):
            bad = read([st.drifted(a, None if chans is None else np.array(chans), k)
                        for st, k in zip(streams, onsets, strict=True)])
            flags = {"flagged_clean": float((clean > 1).mean()), "flagged_faulty": float((bad > 1).mean())}
            for w in (1, *opts.windows):
                rows.append({**base, "fault": name, "window": w, "fault_rows": len(at), **flags,
                             "auroc": auroc(window_means(clean, w), window_means(bad, w))})
    return rows


def _signals(fit: EnsembleFit, u: int, x: np.ndarray,
             novelty: tuple[InputNovelty, KnnNovelty]) -> dict[str, np.ndarray]:
    mu, sigma = predict_members(fit, u, x)
    return unit_signals(mu, sigma, fit.out_scaler.std[u, 0].cpu().numpy(),
                        {"novelty": novelty[0](x), "knn_novelty": novelty[1](x)})
