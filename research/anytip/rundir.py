"""Run directories: what an experiment run leaves behind so it can be trusted and repeated.

`runs/<spec>/<UTC time>/` (or `--out`) holds `config.yaml` (the resolved spec),
`provenance.json` (code version, seeds, registry content hash, unit choice, machine),
`metrics.json` (the rows contract of ARCHITECTURE.md), models and the report.
"""

from __future__ import annotations

import importlib.resources
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import yaml

import anytip
from anytip.errors import AnytipError

ROW_KEYS = ("method", "unit", "calib_samples", "seed")
FINGERTIP_KEYS = ("force_rmse_n", "angle_rmse_rad")  # each target's RMSE (`train.metrics.target_key`)
METRIC_KEYS = (*ROW_KEYS, *FINGERTIP_KEYS)


def builtin(folder: str) -> Path:
    """A folder shipped inside the package: `configs` (the config blocks) or `experiments` (the
    reference specs). In a checkout they are the repository's own folders (linked into the
    package); in an installed wheel, copies."""
    return Path(str(importlib.resources.files("anytip") / folder))


def utc_stamp() -> str:
    return datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ")




def new_run_dir(spec_name: str, out: str | Path | None, root: str | Path = "runs",
                force: bool = False) -> Path:
    """`out`, or `<root>/<spec_name>/<UTC time>/`, created. A directory that holds a finished
    run (its metrics.json) is refused unless `force`, so results are never overwritten by
    mistake; an interrupted run (no metrics yet) may be resumed in place."""
    path = Path(out) if out else Path(root) / spec_name / utc_stamp()
    check_run_dir(path, force)
    path.mkdir(parents=True, exist_ok=True)
    return path


def check_run_dir(path: Path, force: bool = False) -> None:
    """Refuse a run directory that is a file, or holds a finished run unless `force`."""
    if path.exists() and not path.is_dir():
        raise AnytipError(f"{path}: exists and is not a directory")
    if (path / "metrics.json").exists() and not force:
        raise AnytipError(f"{path}: already holds a finished run (metrics.json); choose another --out "
                          "or pass --force to overwrite it")


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


def peak_memory() -> dict[str, float]:
    """The process's peak memory so far, in GB (1e9 bytes): `peak_memory_gb`, its resident set
    (`getrusage`: kB on Linux, bytes on macOS; absent where the platform has no `resource`), and
    `peak_gpu_memory_gb`, what torch allocated on the GPU, where one was used."""
    import torch

    out: dict[str, float] = {}
    if sys.platform != "win32":  # Windows has no `resource`
        import resource

        rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        out["peak_memory_gb"] = round(rss / (1e9 if sys.platform == "darwin" else 1e6), 2)
    if torch.cuda.is_available() and torch.cuda.is_initialized():
        out["peak_gpu_memory_gb"] = round(torch.cuda.max_memory_allocated() / 1e9, 2)
    return out


def finite(data: Any) -> Any:
    """`data` with every NaN or infinite float replaced by None (JSON has no such numbers)
    and numpy scalars and arrays turned into plain Python values."""
    if isinstance(data, dict):
        return {k: finite(v) for k, v in data.items()}
    if isinstance(data, (list, tuple)):
        return [finite(v) for v in data]
    if hasattr(data, "tolist") and not isinstance(data, (str, bytes)):
        return finite(data.tolist())
    if isinstance(data, float) and not math.isfinite(data):
        return None
    return data


def dumps_json(data: Any, indent: int | None = 2, sort_keys: bool = False) -> str:
    """The one JSON writer: strict JSON (non-finite numbers become null), newline-terminated."""
    return json.dumps(finite(data), indent=indent, sort_keys=sort_keys, allow_nan=False) + "\n"


def read_json(path: Path) -> Any:
    """A JSON file as written by `write_json`; unreadable or invalid JSON names the file."""
    def refuse(token: str) -> Any:
        raise ValueError(f"non-standard number {token}")
    try:
        return json.loads(Path(path).read_text(), parse_constant=refuse)
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise AnytipError(f"{path}: not a readable JSON file ({e})") from e


def write_json(path: Path, data: Any, indent: int | None = 2) -> None:
    """Write `dumps_json(data)` atomically (see `write_text`)."""
    write_text(Path(path), dumps_json(data, indent))


def write_text(path: Path, text: str) -> None:
    """Write `text` atomically (see `write_bytes`), UTF-8."""
    write_bytes(path, text.encode("utf-8"))


def write_bytes(path: Path, data: bytes) -> None:
    """Write `data` atomically (temporary file, then rename), readable like any file the
    process writes (the umask decides, as for open())."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_config(run_dir: Path, spec_dict: dict[str, Any]) -> None:
    write_text(run_dir / "config.yaml", yaml.safe_dump(spec_dict, sort_keys=False))


def check_rows(rows: list[dict[str, Any]],
               target_keys: Sequence[str] = FINGERTIP_KEYS) -> list[dict[str, Any]]:
    """Refuse result rows that break the metrics contract (a programming error, not user input):
    every row names its method, unit, calibration samples and seed, and each target's RMSE."""
    for row in rows:
        missing = [k for k in (*ROW_KEYS, *target_keys) if k not in row]
        if missing:
            raise ValueError(f"result row {row} lacks {missing}")
    return rows


def write_metrics(run_dir: Path, rows: list[dict[str, Any]], target_keys: Sequence[str] = FINGERTIP_KEYS,
                  **extra: Any) -> Path:
    path = run_dir / "metrics.json"
    write_json(path, {"results": check_rows(rows, target_keys), **extra})
    return path
