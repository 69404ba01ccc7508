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
    CONTACT_RELEASE_N, the reading taken from its median over the run's first REST_S seconds at rest:
    an F/T offset over the threshold is no contact, and a reading in between keeps the state before."""
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
