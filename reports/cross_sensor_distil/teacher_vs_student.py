"""Research log entry 78's diagnostic: on a validation unit, how far the joint fit's contacts of its
ordinary-use rows (the labels `distil: fitted` trains on) lie from the rows' true contacts, against
the unit's own network calibrated without them, by true force.

    PYTHONPATH=research OMP_NUM_THREADS=1 python reports/cross_sensor_distil/teacher_vs_student.py \
        reports/cross_sensor_distil/other16_none_seed0 SIM23-004 data/other16

It runs `anytip calibrate --budget-seconds 120 --ordinary-use 600` and records what the calibration
read (its ordinary use and the fit's contacts) by wrapping two of its functions; the unit's network
never trains on these rows under `distil: none`.
"""

from __future__ import annotations

import sys
from typing import Any

import numpy as np

import anytip.calibrate.response as cal
from anytip.cli import main
from anytip.models.io import load_models
from anytip.train.metrics import predict

got: dict[str, Any] = {}
_use, _distil = cal.stream_ordinary_use, cal.distilled_rows


def _recorded_use(arrays, unit, stream, seconds, seed):  # type: ignore[no-untyped-def]
    got["arrays"] = arrays
    got["used"] = _use(arrays, unit, stream, seconds, seed)
    return got["used"]


def _recorded_distil(free, X, fitted, truth=None):  # type: ignore[no-untyped-def]
    got.update(free=free, X=X, fitted=fitted)
    return _distil(free, X, fitted, truth)


def rms(e: np.ndarray) -> np.ndarray:
    return np.sqrt((e**2).mean(0)).round(3)


if __name__ == "__main__":
    run, unit, registry = sys.argv[1:4]
    cal.stream_ordinary_use, cal.distilled_rows = _recorded_use, _recorded_distil
    out = f"/tmp/teacher_vs_student_{unit}"
    main(["calibrate", "--model", run, "--unit", unit, "--registry", registry, "--budget-seconds", "120",
          "--method", "response", "--ordinary-use", "600", "--out", out, "--force"])
    arrays, free = got["arrays"], got["free"]
    rows = got["used"].rows[free.read_rows(len(got["used"].rows))]
    truth, fc = arrays.targets[rows], list(arrays.force_columns)
    net = load_models(out + "/model.safetensors")
    teacher = got["fitted"].numpy() - truth
    student = predict(net.model, net.in_scaler, net.out_scaler, got["X"][None].float())[0].numpy() - truth
    F = np.linalg.norm(truth[:, fc], axis=1)
    print("columns", arrays.output_names)
    for lo, hi in ((0, 2), (2, np.inf)):
        m = (F >= lo) & (F < hi)
        print(f"true |F| in [{lo}, {hi}) N, {m.sum()} rows: fit's contacts RMS {rms(teacher[m])}, "
              f"unit network RMS {rms(student[m])}")
    norm = {k: float(np.sqrt((e[:, fc] ** 2).sum(1).mean())) for k, e in (("fit", teacher), ("net", student))}
    print(f"force error norm RMS: fit's contacts {norm['fit']:.3f} N, unit network {norm['net']:.3f} N")
