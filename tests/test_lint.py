"""The code base passes its linter (ruff, configured in pyproject.toml) and holds no repeated
blocks of code (pylint's duplicate-code check)."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def test_ruff_is_clean():
    ruff = shutil.which("ruff") or str(Path(sys.executable).parent / "ruff")
    if not Path(ruff).exists():
        pytest.fail("ruff is not installed; `make test` installs the dev extras")
    result = subprocess.run([ruff, "check", "research", "tests"], cwd=REPO, capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr


def test_no_block_of_code_is_repeated():
    result = subprocess.run([sys.executable, "-m", "pylint", "--disable=all", "--enable=duplicate-code",
                             "--score=n", "research/anytip"], cwd=REPO, capture_output=True, text=True)
    if "No module named pylint" in result.stderr:
        pytest.fail("pylint is not installed; `make test` installs the dev extras")
    assert result.returncode == 0, result.stdout + result.stderr
