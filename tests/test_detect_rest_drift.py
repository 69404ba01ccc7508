"""The rest-drift detector on a tiny fleet: a drifted stream is flagged, a clean one is not."""

import numpy as np
import pytest

from anytip.data.faults import run_streams
from anytip.uncertainty.rest_drift import RestDriftDetector, block_minimum, ewma


def _unit_streams(registry):
    runs = registry.list_runs()
    mine = [r for r in runs if r.unit == runs[0].unit]
    return run_streams(registry, mine, list(range(len(mine))))


def _fit(streams):
    """Fit on the first stream only; the others are never seen."""
    st = streams[0]
    block = 2 * int(np.diff(np.flatnonzero(np.diff(np.r_[0, st.contact.astype(int), 0])))[::2].max())
    return RestDriftDetector.fit([(st.pressure, st.temperature)], [~st.contact & st.after_tare],
                                 [st.after_tare], block, [int(np.argmax(st.contact)) + 1])


@pytest.mark.parametrize("channels", [None, [3]])
def test_drift_of_1kpa_is_flagged_and_a_clean_stream_is_not(small_registry, channels):
    streams = _unit_streams(small_registry)
    assert len(streams) >= 2
    det = _fit(streams)
    for st in streams[1:]:
        start = int(np.argmax(st.contact)) + 1
        watched = np.arange(len(st.contact)) >= start + 3 * det.block_rows  # after the state settles
        clean = det.flag((st.pressure, st.temperature), start)[watched]
        bad = st.drifted(1000.0, None if channels is None else np.array(channels))
        drifted = det.flag((bad.pressure, bad.temperature), start)[watched]
        assert clean.mean() < 0.05, clean.mean()
        assert drifted.mean() > 0.95, drifted.mean()


def test_block_minimum_is_the_median_of_recent_block_lows():
    x = np.arange(20, dtype=float)[:, None] % 5  # lows of 0 in every block of 5
    x[7] = -100.0  # one deep dip in block 1: the median of the last lows ignores it later
    out = block_minimum(x, 5, n_blocks=3)
    assert out[:5, 0].tolist() == [0, 0, 0, 0, 0]  # running minimum in the first block
    assert out[5, 0] == 0 and out[10, 0] == -50 and out[15, 0] == 0
    e = ewma(np.ones((400, 1)), 100.0)
    assert abs(e[-1, 0] - (1 - 0.99 ** 400)) < 1e-9
