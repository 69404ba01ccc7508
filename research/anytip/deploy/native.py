"""Compile an exported C model here with gcc and call `anytip_infer` through ctypes."""

from __future__ import annotations

import ctypes
import functools
import platform
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from anytip.errors import AnytipError

CFLAGS = ("-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic", "-shared", "-fPIC")


@functools.cache
def fma_flags() -> tuple[str, ...]:
    """Flags that make the host build fuse `a += w * x` into one rounding, as the Cortex-M4F build
    does (-ffp-contract=fast on its VFMA), so the host computes the device's sums; () where this
    CPU has no fused multiply-add (x86-64 without the FMA extension)."""
    machine = platform.machine().lower()
    if machine in ("aarch64", "arm64"):
        return ("-ffp-contract=fast",)
    if machine in ("x86_64", "amd64"):
        try:
            flags = Path("/proc/cpuinfo").read_text()
        except OSError:
            return ()
        return ("-mfma", "-ffp-contract=fast") if " fma " in flags.replace("\n", " ") else ()
    return ()


def compile_shared(source: str | Path, out: str | Path, cc: str = "gcc", includes: tuple[str, ...] = (),
                   strict: bool = True, fused: bool = True) -> Path:
    """gcc -std=c99 -O2 -Wall -Wextra -Werror -pedantic -shared (+ `fma_flags`): source -> a shared
    library (no -lm). `fused=False` keeps every multiply and add separately rounded."""
    if shutil.which(cc) is None:
        raise AnytipError(f"C compiler {cc!r} not found on PATH (needed to verify the C export)")
    out = Path(out)
    base = CFLAGS if strict else ("-std=gnu99", "-O2", "-shared", "-fPIC")
    flags = (*base, *(fma_flags() if fused else ()))
    inc = [f"-I{d}" for d in includes]
    res = subprocess.run([cc, *flags, *inc, "-o", str(out), str(source), *([] if strict else ["-lm"])],
                         capture_output=True, text=True)
    if res.returncode != 0:
        raise AnytipError(f"{source}: gcc failed:\n{res.stderr.strip()}")
    return out


def run_c(source: str | Path, x: np.ndarray, n_out: int, includes: tuple[str, ...] = (),
          strict: bool = True, fused: bool = True) -> np.ndarray:
    """Compile `source` and evaluate x (B, n_in) row by row: -> (B, n_out) float64. `strict`
    builds anytip's own C (C99, all warnings as errors, no libm); peers' code builds as gnu99 with -lm."""
    with tempfile.TemporaryDirectory() as tmp:
        lib = ctypes.CDLL(str(compile_shared(source, Path(tmp) / "libanytip.so", includes=includes,
                                             strict=strict, fused=fused)))
        fn = lib.anytip_infer
        fn.argtypes = [ctypes.POINTER(ctypes.c_float), ctypes.POINTER(ctypes.c_float)]
        fn.restype = None
        xin = np.ascontiguousarray(x, dtype=np.float32)
        y = np.zeros((len(xin), n_out), dtype=np.float32)
        ptr = ctypes.POINTER(ctypes.c_float)
        for r in range(len(xin)):
            fn(xin[r].ctypes.data_as(ptr), y[r].ctypes.data_as(ptr))
    return y.astype(np.float64)
