"""Private scratch directories for registry writes, and removal of those left by dead processes.

A writer owns `tmp/<token>/` while it holds an exclusive flock on `tmp/<token>.lock`.
The kernel drops the lock when the process dies, however it dies, so a lock that can
be taken names a dead writer and its scratch directory can go. A live writer's
scratch files are never touched.
"""

from __future__ import annotations

import fcntl
import os
import shutil
import uuid
from pathlib import Path


class Staging:
    """A scratch directory inside `tmp_root`, alive until `close()` (or the `with` block ends)."""

    def __init__(self, tmp_root: Path):
        tmp_root.mkdir(parents=True, exist_ok=True)
        self.fd, self.lock_path = _take_new_lock(tmp_root)
        self.dir = tmp_root / self.lock_path.stem
        self.dir.mkdir()

    def close(self) -> None:
        shutil.rmtree(self.dir, ignore_errors=True)
        self.lock_path.unlink(missing_ok=True)
        os.close(self.fd)

    def __enter__(self) -> Staging:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _take_new_lock(tmp_root: Path) -> tuple[int, Path]:
    while True:
        path = tmp_root / f"{os.getpid()}-{uuid.uuid4().hex}.lock"
        fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_RDWR, 0o644)
        fcntl.flock(fd, fcntl.LOCK_EX)
        # A cleaner may have taken and removed the file between open and flock.
        try:
            ours = os.stat(path).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            ours = False
        if ours:
            return fd, path
        os.close(fd)


def clean_stale(tmp_root: Path) -> list[str]:
    """Remove scratch directories and lock files of dead writers; return their names."""
    if not tmp_root.is_dir():
        return []
    removed = []
    for lock in sorted(tmp_root.glob("*.lock")):
        if _remove_if_unlocked(lock):
            removed.append(lock.stem)
    for entry in sorted(tmp_root.iterdir()):
        # A directory whose lock is gone belongs to nobody (writers lock before mkdir).
        if entry.is_dir() and not entry.with_name(entry.name + ".lock").exists():
            shutil.rmtree(entry, ignore_errors=True)
            removed.append(entry.name)
    return removed


def _remove_if_unlocked(lock: Path) -> bool:
    try:
        fd = os.open(lock, os.O_RDWR)
    except FileNotFoundError:
        return False
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            return False
        shutil.rmtree(lock.with_suffix(""), ignore_errors=True)
        lock.unlink(missing_ok=True)
        return True
    finally:
        os.close(fd)
