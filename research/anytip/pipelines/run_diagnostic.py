"""The command-line frame of the scripts that re-examine a finished cross_sensor run.

Each such script (`scripts/where_calibration_errs.py`, `scripts/episodic_transfer.py`) takes
the run directory, the registry it ran on, one budget in robot seconds, the seeds and the
adapter kind, computes lines per seed and prints one markdown text, optionally also to a file.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import torch

from anytip.config import load_spec

Line = TypeVar("Line")


def diagnostic_parser(doc: str) -> argparse.ArgumentParser:
    """Arguments every run diagnostic takes: run, --registry, --budget, --seeds, --adapter, --out."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("run", type=Path, help="a finished cross_sensor run directory")
    ap.add_argument("--registry", required=True, help="the registry the run read")
    ap.add_argument("--budget", type=float, default=120.0, help="robot seconds (a budget of the run)")
    ap.add_argument("--seeds", type=int, nargs="+", default=None, help="default: the run's seeds")
    ap.add_argument("--adapter", default="input_affine+film")
    ap.add_argument("--out", type=Path, default=None, help="also write the text here")
    return ap


def diagnose(
    args: argparse.Namespace,
    per_seed: Callable[[int], list[Line]],
    render: Callable[[list[int], list[Line]], str],
) -> str:
    """Lines of every seed (one CPU thread), rendered, printed and written to `args.out`."""
    torch.set_num_threads(1)
    seeds = args.seeds or load_spec(args.run / "config.yaml").all_seeds
    text = render(seeds, [line for s in seeds for line in per_seed(s)])
    print(text)
    if args.out:
        args.out.write_text(text)
    return text
