"""Training arrays: tare from rest rows, contact rows only, patches from label angles."""

import numpy as np
import pytest

from anytip.data.arrays import (
    CONTACT_FORCE_N,
    CONTACT_RELEASE_N,
    REST_S,
    force_contact,
    load_arrays,
    patch_index,
    rest_reading,
)
from anytip.errors import AnytipError


def test_patch_index_grid_edges():
    deg = np.array([[-45, -135], [-30.01, -120.01], [-30, -120], [44.9, 44.9], [60, 90]])
    idx = patch_index(np.radians(deg))
    assert idx.tolist() == [0, 0, 13, 5 * 12 + 11, 5 * 12 + 11]


def test_rest_reading_uses_rows_before_first_contact():
    p = np.array([[1.0], [3.0], [100.0], [7.0]])
    contact = np.array([False, False, True, False])
    assert rest_reading(p, contact, "x")[0] == 2.0
    with pytest.raises(AnytipError, match="x: no contact-free rows"):
        rest_reading(p, np.ones(4, bool), "x")


def test_force_contact_keeps_a_press_whole_where_its_reading_dithers_about_the_threshold():
    """Without `in_contact` a contact starts at |F| >= CONTACT_FORCE_N and lasts until |F| falls below
    CONTACT_RELEASE_N (a noiseless reading: the thresholds' floors), the reading taken from its median
    over the run's first REST_S seconds at rest: an F/T offset over the threshold is no contact, and a
    reading in between keeps the state before."""
    lo, hi = CONTACT_RELEASE_N, CONTACT_FORCE_N
    band = (lo + hi) / 2
    rest = int(REST_S * 200)
    magnitude = [0.1, band, hi, 5.0, band, hi + 0.05, band, lo - 0.01, 0.1, band, hi + 0.1]
    expected = [False] * rest + [False, False, True, True, True, True, True, False, False, False, True]
    offset = np.array([0.4, -0.3, 0.2])  # |offset| 0.54 N, over the threshold by itself
    force = np.tile(offset, (rest + len(magnitude), 1))
    force[rest:, 2] -= magnitude
    force[rest // 4, 2] -= 1.0  # one row of the rest in contact, as a file may break the promise
    time = np.arange(len(force)) / 200.0
    expected[rest // 4] = True
    assert force_contact(force, time).tolist() == expected
    assert force_contact(np.zeros((0, 3)), np.zeros(0)).tolist() == []


def test_force_contact_reads_a_noisy_sensor_by_its_own_noise():
    """An F/T sensor with 0.3 N of noise per axis and an offset: its contacts start at 7 and end at 3.5
    times the noise its first 0.5 s at rest show, so five trapezoid presses of 5 N are five contacts,
    each within its press, where the fixed thresholds alone find contacts all through the rest."""
    g = np.random.default_rng(0)
    time = np.arange(int(12 * 200)) / 200.0
    truth = np.zeros_like(time)
    for start in (1.0, 3.0, 5.0, 7.0, 9.0):  # 0.1 s ramps either side of 0.8 s at 5 N
        truth += 5 * np.clip(np.minimum(time - start, start + 1.0 - time) / 0.1, 0, 1)
    force = np.array([0.5, -0.2, 0.3]) + 0.3 * g.standard_normal((len(time), 3))
    force[:, 2] -= truth
    found = force_contact(force, time)
    edges = np.diff(np.concatenate([[0], found.astype(int), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    assert len(starts) == 5 and all(truth[a:b].min() > 0 for a, b in zip(starts, ends, strict=True))
    fixed = np.linalg.norm(force - np.median(force[time < REST_S], axis=0), axis=1) >= CONTACT_FORCE_N
    assert np.count_nonzero(fixed & (truth == 0)) > 100


def test_a_run_whose_force_cannot_show_its_contacts_is_refused_by_name(tmp_path):
    """A run without `in_contact` whose force spreads over its first 0.5 s (at rest, the format says) by as
    much as a contact's threshold: no threshold tells its contacts from that, and reading it says so."""
    from anytip.data.registry import Registry
    from run_factory import make_run

    registry = Registry(tmp_path / "r")
    registry.add_runs([make_run("LAB-1", n=600, optional=False)])  # random forces from its first row
    (record,) = registry.list_runs()
    said = (rf"run {record.run_id}: it has no in_contact, and its force over its first 0.5 s, which the "
            r"format keeps at rest, spreads by [0-9.]+ N per axis")
    with pytest.raises(AnytipError, match=said):
        load_arrays(registry, [record])


def test_load_arrays_tares_and_keeps_contact_rows(small_registry):
    records = small_registry.list_runs()
    arrays = load_arrays(small_registry, records)
    run = small_registry.open_run(records[0].run_id)
    contact = run.in_contact
    first = int(np.argmax(contact))
    tare = run.pressure[:first].astype(np.float64).mean(0)
    rows = arrays.run == 0
    assert rows.sum() == contact.sum()
    np.testing.assert_allclose(arrays.pressure[rows], run.pressure[contact] - tare, atol=0.02)
    np.testing.assert_array_equal(arrays.force[rows], run.force[contact])
    assert arrays.units == sorted({r.unit for r in records})
    assert arrays.targets.shape == (arrays.n_rows, 5)
    # every protocol patch maps to one cell per orientation's press points
    assert len(np.unique(arrays.patch[rows])) == 4


def test_load_arrays_refuses_mixed_models(small_registry):
    recs = small_registry.list_runs()
    other = type(recs[0])(**{**recs[0].__dict__, "sensor_model": "other-model"})
    with pytest.raises(AnytipError, match="mix sensor models"):
        load_arrays(small_registry, [recs[0], other])
