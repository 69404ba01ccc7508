"""An installed wheel runs without the checkout: it finds its config blocks and the quickstart spec
in the package, and a spec copied anywhere runs."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> Path:
    """The wheel built from this checkout, unpacked with pip into a folder of its own."""
    work = tmp_path_factory.mktemp("wheel")
    build = subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "--no-build-isolation",
                            "-w", str(work / "dist"), str(REPO)], capture_output=True, text=True, timeout=300)
    assert build.returncode == 0, build.stderr
    wheel = next((work / "dist").glob("anytip-*.whl"))
    target = work / "site"
    install = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target",
                              str(target), str(wheel)], capture_output=True, text=True, timeout=300)
    assert install.returncode == 0, install.stderr
    return target


def run_installed(target: Path, cwd: Path, *args: str) -> subprocess.CompletedProcess:
    """`anytip ARGS` from the installed copy, in `cwd`, with the checkout nowhere on the path."""
    env = {**os.environ, "PYTHONPATH": str(target)}
    env.pop("ANYTIP_REGISTRY", None)
    code = ("import sys, anytip; from anytip.cli import main; "
            f"assert anytip.__file__.startswith({str(target)!r}), anytip.__file__; sys.exit(main())")
    return subprocess.run([sys.executable, "-c", code, *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=600)


def test_the_wheel_ships_its_blocks_and_specs(installed):
    pkg = installed / "anytip"
    assert (pkg / "configs" / "training" / "fast.yaml").is_file()
    assert (pkg / "configs" / "budgets" / "stm32f334.yaml").is_file()
    assert (pkg / "configs" / "csv" / "rig34.yaml").is_file()
    assert (pkg / "experiments" / "quickstart.yaml").is_file()
    assert not (pkg / "configs").is_symlink()


def test_a_copied_spec_runs_from_the_installed_wheel(installed, tmp_path):
    elsewhere = tmp_path / "lab"
    elsewhere.mkdir()
    spec = elsewhere / "my_quickstart.yaml"
    shutil.copy(REPO / "experiments" / "quickstart.yaml", spec)
    result = run_installed(installed, elsewhere, "run", str(spec), "--registry", str(elsewhere / "reg"),
                           "--out", str(elsewhere / "run"), "--set", "training.epochs=1",
                           "--set", "simulate_if_empty.units=2",
                           "--set", "simulate_if_empty.protocols=[short]", "--set", "data.protocol=short")
    assert result.returncode == 0, result.stderr[-2000:]
    assert (elsewhere / "run" / "metrics.json").is_file()
    assert (elsewhere / "run" / "report.md").is_file()
