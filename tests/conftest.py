"""Shared fixtures: a small simulated fleet in a registry (short protocol, seconds to make)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import torch

from anytip.data.registry import Registry
from anytip.data.simulated import simulate_into
from anytip.sensor.fleet import FleetConfig
from anytip.sensor.protocols import Protocol

SMALL_UNITS = 8
# A calibration protocol a few seconds long, beside the short protocol the units are tested on.
QUICK = Protocol(name="quick", patches=3, layers_n=(12.5,), orientations_deg=(0.0,))

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


@pytest.fixture(scope="module")
def two_protocol_registry(tmp_path_factory) -> Registry:
    """8 default-fleet units with the short protocol and the seconds-long QUICK one (cross-sensor
    tests; one per test module)."""
    registry = Registry(tmp_path_factory.mktemp("cross"))
    simulate_into(registry, FleetConfig(), 8, seed=11, protocols=("short", QUICK))
    return registry
