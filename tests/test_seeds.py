"""Seeds derived from a spec's seed: one home, no collisions within a stream at fleet scale."""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import pytest

from anytip.data import seeds
from anytip.data.seeds import Stream, stream_seed, unit_seed

ROOT = Path(__file__).resolve().parents[1] / "research" / "anytip"
STREAMS = [v for v in vars(seeds).values() if isinstance(v, Stream)]
# The streams that split a fleet's units (test patches, validation rows, calibration):
# fleets of up to 1024 units (the GPU fleets) must get one draw per unit.
SPLIT_STREAMS = [seeds.TEST_PATCHES, seeds.VALIDATION_PATCHES, seeds.CALIBRATION_PATCHES,
                 seeds.VALIDATION_ROWS, seeds.CALIBRATION_ROWS]


@pytest.mark.parametrize("stream", STREAMS, ids=lambda s: s.name)
def test_a_stream_gives_distinct_seeds_below_its_index_bound(stream: Stream):
    n = min(stream.distinct_indices, 3000)
    drawn = [stream_seed(stream, s, i) for s in range(8) for i in range(n)]
    assert len(set(drawn)) == len(drawn)
    # one index further, seeds s and s + 1 collide: the bound is tight, not a guess
    assert stream_seed(stream, 0, stream.distinct_indices) == stream_seed(stream, 1, 0)


@pytest.mark.parametrize("stream", SPLIT_STREAMS, ids=lambda s: s.name)
def test_split_streams_cover_a_thousand_unit_fleet(stream: Stream):
    assert stream.distinct_indices >= 1024


def test_stream_names_are_unique():
    assert len({s.name for s in STREAMS}) == len(STREAMS)


def test_unit_seed_depends_on_seed_unit_and_stream_only():
    keys = itertools.product(range(4), range(64), ["init", "sample"])
    grid = [unit_seed(s, u, name) for s, u, name in keys]
    assert len(set(grid)) == len(grid)
    assert all(0 <= x < 2**63 for x in grid)
    assert unit_seed(3, 5, "sample") == unit_seed(3, 5, "sample")


def test_no_seed_is_derived_outside_the_seeds_module():
    """An arithmetic seed formula (seed * 7919 + u, 10_000 + seed) anywhere but data/seeds.py
    is a stream without a name; the simulator's SeedSequence lists are not arithmetic."""
    formula = re.compile(r"\bseed\s*[*+]\s*\w|\w\s*[*+]\s*seed\b")
    found = [f"{p.relative_to(ROOT)}:{i}: {line.strip()}"
             for p in sorted(ROOT.rglob("*.py")) if p.name != "seeds.py"
             for i, line in enumerate(p.read_text().splitlines(), 1)
             if formula.search(line.split("#")[0])]
    assert found == []
