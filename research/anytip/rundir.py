"""Run directories: what an experiment run leaves behind so it can be trusted and repeated.

`runs/<spec>/<UTC time>/` (or `--out`) holds `config.yaml` (the resolved spec),
`provenance.json` (code version, seeds, registry content hash, unit choice, machine),
`metrics.json` (the rows contract of ARCHITECTURE.md), models and the report.
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import tempfile
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import yaml

import anytip

METRIC_KEYS = ("method", "unit", "calib_samples", "seed", "force_rmse_n", "angle_rmse_rad")


def utc_stamp() -> str:
    return datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ")


def new_run_dir(spec_name: str, out: str | Path | None, root: str | Path = "runs") -> Path:
    path = Path(out) if out else Path(root) / spec_name / utc_stamp()
    path.mkdir(parents=True, exist_ok=True)
    return path


def code_version() -> dict[str, Any]:
    """Package version and, inside a git checkout, the commit and whether it was modified."""
    info: dict[str, Any] = {"anytip": anytip.__version__}
    src = Path(anytip.__file__).resolve().parent
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=src, capture_output=True,
                                text=True, timeout=5, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=src,
                               capture_output=True, text=True, timeout=5, check=True).stdout.strip()
        info.update(git_commit=commit, git_dirty=bool(dirty))
    except (OSError, subprocess.SubprocessError):
        info["git_commit"] = None
    return info


def machine() -> dict[str, Any]:
    import torch

    return {
        "python": platform.python_version(), "torch": torch.__version__,
        "platform": platform.platform(), "cpus": os.cpu_count(),
        "torch_threads": torch.get_num_threads(),
        "cuda": torch.cuda.get_device_name(0) if torch.cuda.is_available() else None,
    }


def write_json(path: Path, data: Any) -> None:
    """Write JSON atomically (temporary file, then rename)."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    with os.fdopen(fd, "w") as f:
        json.dump(data, f, indent=2, sort_keys=False, default=_json_default)
        f.write("\n")
    os.replace(tmp, path)


def _json_default(value: Any) -> Any:
    if hasattr(value, "item"):
        return value.item()
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")


def write_config(run_dir: Path, spec_dict: dict[str, Any]) -> None:
    (run_dir / "config.yaml").write_text(yaml.safe_dump(spec_dict, sort_keys=False))


def check_rows(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Refuse result rows that break the metrics contract (a programming error, not user input)."""
    for row in rows:
        missing = [k for k in METRIC_KEYS if k not in row]
        if missing:
            raise ValueError(f"result row {row} lacks {missing}")
    return rows


def write_metrics(run_dir: Path, rows: list[dict[str, Any]], **extra: Any) -> Path:
    path = run_dir / "metrics.json"
    write_json(path, {"results": check_rows(rows), **extra})
    return path
