"""Every random stream the library derives from a spec's seed, named, in one place.

A spec gives one seed per repetition (`seeds: [0, 1, 2]`). Each use of randomness under it
(which patches a unit holds out, which of its rows validate, a conformal fold, a bootstrap,
a search worker) draws from its own named stream:

    stream_seed(STREAM, seed, index) = seed * STREAM.scale + STREAM.offset + index

where `index` is usually the unit's position in the fleet. Within one stream two
(seed, index) pairs share a seed only when an index reaches the stream's scale
(`Stream.distinct_indices`); the splits' streams use primes far above any fleet size. The
uncertainty pipeline's fold, fold-model and fault streams have small scales (7, 13, 31):
beyond that many units, seed s + 1 repeats some of seed s's draws for other units. They are
kept because the committed uncertainty report was made with them.

`unit_seed` is the other derivation: a 63-bit seed from (seed, unit, stream name) through
NumPy's SeedSequence, for weight initialisation and minibatch sampling, where the streams
of different units must not overlap whatever the fleet size.
"""

from __future__ import annotations

import zlib
from typing import NamedTuple

import numpy as np


class Stream(NamedTuple):
    """A linear seed stream: seed * scale + offset + index."""

    name: str
    scale: int
    offset: int = 0

    @property
    def distinct_indices(self) -> int:
        """Indices 0..n-1 give distinct seeds for every seed >= 0 when n <= this."""
        return self.scale


TEST_PATCHES = Stream("test patches or rows of unit u", 100_003)
# a factor unit's own, by its place among the factor units, so that its test patches (and with them its plan
# and what it teaches the fleet factor) do not depend on how many units a fold holds out
FACTOR_TEST_PATCHES = Stream("test patches of factor unit i", 100_003, 50_000)
VALIDATION_PATCHES = Stream("validation patches of a calibrated unit u", 100_003, 7919)
CALIBRATION_PATCHES = Stream("conformal calibration patches of unit u", 100_003, 77)
VALIDATION_ROWS = Stream("validation rows of unit u", 7919)
CALIBRATION_ROWS = Stream("validation rows of a calibrated unit u", 7919, 1000)
FOLD_ROWS = Stream("validation rows of fold k of unit u (index 31 u + k)", 7919)
PATCH_FOLDS = Stream("cross-conformal patch folds of unit u", 7, 501)
FOLD_MODEL = Stream("which fold model scores unit u", 13)
FAULT_ROWS = Stream("rows a fault is injected into, unit u", 31)
BOOTSTRAP = Stream("bootstrap of unit or budget m", 1009)
UNSEEN_ROWS = Stream("test rows of budget m", 4099)
ENSEMBLE_MEMBER = Stream("ensemble member k > 0", 1000)
REFERENCE_START = Stream("start j of a per-unit reference (index 1000 j; start 0 is the seed's own)", 1)
FOREIGN_UNITS = Stream("simulated foreign unit k", 97, 10_000)
SEARCH_WORKER = Stream("search sampler of worker w", 1000)
SEARCH_TEST_SCORER = Stream("test scorer of an architecture search", 1, 1)


def stream_seed(stream: Stream, seed: int, index: int = 0) -> int:
    """The seed of `index` (a unit, fold or member) in `stream` under the spec's `seed`."""
    return seed * stream.scale + stream.offset + index


def unit_seed(seed: int, unit: int, stream: str = "init") -> int:
    """A 63-bit seed for one unit's random stream that does not depend on the fleet size."""
    entropy = [seed, unit, zlib.crc32(stream.encode())]
    return int(np.random.SeedSequence(entropy).generate_state(1, np.uint64)[0] >> 1)
