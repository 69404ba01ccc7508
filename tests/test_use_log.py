"""Ordinary-use logs (pressures alone) and the contacts found in them: the reader's checks on files made
from the format's description, the detector on signals whose contacts are known, and the rows a calibration
reads."""

import h5py
import numpy as np
import pytest

from anytip.data.contact import ContactDetector
from anytip.data.runfile import RunFormatError
from anytip.data.use_log import UseLog, read_use_log, use_rows, write_use_log

RATE = 200.0


def pressed(seed: int = 0) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """Time (n,) s and absolute pressures (n, 4) Pa of a unit at rest, pressed twice: each press loads three
    barometers by up to 20 kPa over 0.4 s, holds 0.5 s, unloads over 0.4 s to 1 kPa (5% of its peak, where
    the force is gone), and the dome then lets go of it with a time constant of 0.5 s; noise of 8 Pa and a
    drift of 60 Pa over the 20 s. Also the rows of each kind: `firm` (a press above 4 kPa), `recovery`
    (after a press), `rest`."""
    g = np.random.default_rng(seed)
    t = np.arange(int(20 * RATE)) / RATE
    signal = np.zeros_like(t)
    kinds = {"firm": np.zeros(len(t), bool), "recovery": np.zeros(len(t), bool)}
    for start in (3.0, 11.0):
        up, hold, down = start + 0.4, start + 0.9, start + 1.3
        shape = np.interp(t, [start, up, hold, down], [0.0, 20000.0, 20000.0, 1000.0], left=0.0, right=0.0)
        after = t >= down
        shape[after] = 1000.0 * np.exp(-(t[after] - down) / 0.5)
        signal = np.maximum(signal, shape)
        kinds["firm"] |= (t > start) & (t < down) & (shape > 4000.0)
        kinds["recovery"] |= (t > down) & (t < down + 4.0)
    pressure = 1e5 + 60.0 * t[:, None] / 20 + 8.0 * g.standard_normal((len(t), 4))
    pressure[:, :3] += signal[:, None] * np.array([1.0, 0.6, 0.3])
    kinds["rest"] = (t < 3.0) | ((t > 6.0) & (t < 11.0))
    return t, pressure, kinds


def test_the_detector_finds_presses_and_lets_the_recovery_go():
    t, p, kinds = pressed()
    found = ContactDetector().contact(t, p, RATE)
    assert found[kinds["firm"]].all()
    assert not found[kinds["recovery"]].any()  # 1 kPa and falling: under a tenth of the press's 20 kPa
    assert not found[kinds["rest"]].any()  # the drift of 60 Pa stays under the 200 Pa threshold
    no_fraction = ContactDetector(fraction=0.0).contact(t, p, RATE)
    # a plain threshold keeps the recovery while it stands over 200 Pa above the tracked rest
    assert no_fraction[kinds["recovery"]].sum() >= 0.3 * RATE
    assert not ContactDetector().contact(t, np.full_like(p, 1e5), RATE).any()


def test_use_rows_are_the_found_rows_tared_by_the_rest_before_them(tmp_path):
    t, p, kinds = pressed()
    log = UseLog("FT-0001", "fingertip-8baro-r10", RATE, "2024-05-01T12:00:00Z", t, p.astype(np.float32))
    found = ContactDetector().contact(t, log.pressure, RATE)
    rows, seconds = use_rows(log, 600.0)
    rest = log.pressure[: int(np.argmax(found))].astype(np.float64).mean(0)
    assert np.allclose(rows, log.pressure[found] - rest, atol=1e-2) and seconds == found.sum() / RATE
    some, got = use_rows(log, 0.5)
    assert len(some) == int(0.5 * RATE) and got == 0.5
    flat = UseLog("FT-0001", "fingertip-8baro-r10", RATE, "2024-05-01T12:00:00Z", t, np.full_like(p, 1e5))
    none, zero = use_rows(flat, 600.0)
    assert none.shape == (0, 4) and zero == 0.0


def test_a_use_log_round_trips_and_every_bad_file_is_named(tmp_path):
    t, p, _ = pressed()
    log = UseLog("FT-0001", "fingertip-8baro-r10", RATE, "2024-05-01T12:00:00Z", t, p.astype(np.float32),
                 np.full(p.shape, 25.0, np.float32))
    path = write_use_log(log, tmp_path / "use.h5")
    back = read_use_log(path)
    assert (back.sensor_id, back.sample_rate_hz) == ("FT-0001", RATE)
    assert np.array_equal(back.pressure, log.pressure) and np.array_equal(back.temperature, log.temperature)

    def crafted(name: str, change) -> str:  # noqa: ANN001 - a function of the open file
        bad = tmp_path / name
        bad.write_bytes(path.read_bytes())
        with h5py.File(bad, "a") as f:
            change(f)
        with pytest.raises(RunFormatError) as e:
            read_use_log(bad)
        assert str(bad) in str(e.value)
        return str(e.value)

    def nan(f: h5py.File) -> None:
        f["pressure"][5, 1] = np.nan

    def backwards(f: h5py.File) -> None:
        f["time"][7] = -1.0

    def linked(f: h5py.File) -> None:
        del f["pressure"]
        f["pressure"] = h5py.ExternalLink("elsewhere.h5", "/pressure")

    assert "NaN or infinite values (first at row 5)" in crafted("nan.h5", nan)
    assert "'time' decreases at row 7" in crafted("back.h5", backwards)
    assert "external link" in crafted("link.h5", linked)
    assert "missing dataset 'pressure'" in crafted("gone.h5", lambda f: f.__delitem__("pressure"))
    assert "expected 'ordinary_use_log'" in crafted("run.h5", lambda f: f.attrs.__setitem__("format",
                                                                                             "calibration_run"))
    assert "sensor_id" in crafted("id.h5", lambda f: f.attrs.__setitem__("sensor_id", "no spaces"))
    (tmp_path / "text.h5").write_text("not hdf5")
    with pytest.raises(RunFormatError, match="not a readable HDF5 file"):
        read_use_log(tmp_path / "text.h5")
