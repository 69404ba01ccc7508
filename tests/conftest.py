"""Shared fixtures: a small simulated fleet in a registry (short protocol, seconds to make)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import torch

from anytip.data.registry import Registry
from anytip.data.simulated import simulate_into
from anytip.sensor.fleet import FleetConfig

SMALL_UNITS = 8

# Tiny models on a shared 2-core machine: one thread per test worker avoids oversubscription.
torch.set_num_threads(1)


@pytest.fixture(scope="session")
def small_registry_master(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("small_registry")
    simulate_into(Registry(root), FleetConfig(), SMALL_UNITS, seed=11, protocols=("short",))
    return root


@pytest.fixture
def small_registry(small_registry_master: Path, tmp_path: Path) -> Registry:
    """A private copy of the session's 8-unit short-protocol registry."""
    root = tmp_path / "registry"
    shutil.copytree(small_registry_master, root)
    return Registry(root)


REPO = Path(__file__).resolve().parents[1]
