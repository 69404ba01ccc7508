"""Calibration protocols: labels stay in their 15-degree cells; forces in range and cone."""

import numpy as np
import pytest

from anytip.errors import AnytipError
from anytip.sensor.protocols import (
    LONG_PLAN_S,
    PROTOCOLS,
    Protocol,
    build_trajectory,
    design_protocol,
    patch_cells,
    press_summary,
)


def _bins(angles_rad):
    deg = np.rad2deg(angles_rad.astype(np.float64))
    return np.stack([np.floor((deg[:, 0] + 45) / 15), np.floor((deg[:, 1] + 135) / 15)], -1).astype(
        int
    )


@pytest.mark.parametrize("orientation", [0.0, -45.0, -90.0])
def test_full_protocol_labels_stay_in_their_cells(orientation):
    traj = build_trajectory(PROTOCOLS["full"], orientation, np.random.default_rng(0))
    assert traj.cells.shape == (36, 2) and len({tuple(c) for c in traj.cells}) == 36
    # binned as the loader does, on float32 labels as stored
    np.testing.assert_array_equal(_bins(traj.angles.astype(np.float32)), traj.cells[traj.patch])
    phi = np.rad2deg(traj.angles[:, 1])
    assert phi.min() > orientation - 45 and phi.max() < orientation + 45


def test_full_protocol_size():
    full = PROTOCOLS["full"]
    rows = len(full.orientations_deg) * full.rows_per_orientation()
    assert 300_000 <= rows <= 400_000
    assert full.duration_s == pytest.approx(rows / 200.0)


def test_short_protocol_is_short_and_spread():
    short = PROTOCOLS["short"]
    assert 60 <= short.duration_s <= 120
    cells = np.concatenate([patch_cells(short, o) for o in short.orientations_deg])
    assert len(np.unique(cells[:, 0])) >= 3 and len(np.unique(cells[:, 1])) >= 6


def test_forces_within_range_and_friction_cone():
    protocol = Protocol(name="t", patches=3, orientations_deg=(0.0,))
    f = build_trajectory(protocol, 0.0, np.random.default_rng(1)).force
    fn, shear = -f[:, 2], np.hypot(f[:, 0], f[:, 1])
    assert fn.min() >= 0 and fn.max() <= 25.0 + 1e-9
    assert np.all(shear <= np.minimum(15.0, 0.8 * fn) + 1e-9)
    assert shear.max() > 10.0


def test_rest_rows_are_out_of_contact_with_zero_force():
    traj = build_trajectory(PROTOCOLS["short"], -45.0, np.random.default_rng(2))
    rest = ~traj.in_contact
    assert 0.05 < rest.mean() < 0.5
    assert np.all(traj.force[rest] == 0.0)
    assert np.all(traj.force[traj.in_contact, 2] < 0.0)


def test_protocol_rejects_off_grid_orientation():
    with pytest.raises(ValueError, match="grid"):
        Protocol(name="bad", orientations_deg=(10.0,))


def test_sweep_cycles_force_layers_over_spread_patches():
    """One press per patch; consecutive presses take the four layers in turn, so the first
    four patches already span 6-25 N, and `layer_cycle` is stored only when set."""
    sweep = PROTOCOLS["sweep"]
    traj = build_trajectory(sweep, 0.0, np.random.default_rng(3))
    assert len(traj.force) == sweep.rows_per_orientation()
    assert traj.press.max() + 1 == sweep.patches == len(np.unique(traj.patch))
    peaks = np.array([-traj.force[traj.press == p, 2].min() for p in range(8)])
    np.testing.assert_allclose(peaks / np.tile(sweep.layers_n, 2), 1.0, atol=0.1)
    assert len(np.unique(traj.cells[:4, 0])) >= 3  # spread, not neighbours
    np.testing.assert_array_equal(_bins(traj.angles.astype(np.float32)), traj.cells[traj.patch])
    assert sweep.to_json()["layer_cycle"] is True and "layer_cycle" not in PROTOCOLS["full"].to_json()


def test_layers_per_patch_presses_each_patch_at_the_next_layers_of_the_cycle():
    """With `layers_per_patch` 2, each patch holds two presses in its cell, the next two force
    layers in turn (the cycle running on across patches); the field is stored only when set, and
    asks for `layer_cycle`."""
    two = PROTOCOLS["sweep"].model_copy(update={"layers_per_patch": 2, "patches": 6})
    two = Protocol.model_validate(two.model_dump())
    traj = build_trajectory(two, 0.0, np.random.default_rng(5))
    assert len(traj.force) == two.rows_per_orientation()
    assert traj.press.max() + 1 == 12 and len(np.unique(traj.patch)) == 6
    peaks = np.array([-traj.force[traj.press == p, 2].min() for p in range(12)])
    np.testing.assert_allclose(peaks / np.tile(two.layers_n, 3), 1.0, atol=0.1)
    np.testing.assert_array_equal(_bins(traj.angles.astype(np.float32)), traj.cells[traj.patch])
    assert two.to_json()["layers_per_patch"] == 2 and "layers_per_patch" not in PROTOCOLS["sweep"].to_json()
    with pytest.raises(ValueError, match="layer_cycle"):
        Protocol(name="x", layers_per_patch=2)


@pytest.mark.parametrize(("seconds", "press_s", "per_patch"),
                         [(120.0, 2.57, 1), (450.0, 2.57, 1), (525.0, 3.93, 4), (600.0, 3.93, 4)])
def test_a_long_designed_plan_presses_each_patch_as_the_full_protocol_does(seconds, press_s, per_patch):
    """Under LONG_PLAN_S (525 s) one press per point, each after a move; from it on, a patch's four force
    levels 0.15 s apart, each press the full protocol's (research log entries 139, 141 and 145). All fit the
    budget."""
    plan = design_protocol(seconds)
    assert plan.duration_s + 30.0 * (len(plan.orientations_deg) - 1) <= seconds
    assert plan.presses_per_patch == per_patch
    press = plan.segment_samples().sum() / plan.sample_rate_hz
    assert press == pytest.approx(press_s, abs=0.01)
    traj = build_trajectory(plan, 0.0, np.random.default_rng(0))
    peaks = np.array([-traj.force[traj.press == p, 2].min() for p in range(per_patch)])
    np.testing.assert_allclose(peaks, plan.layers_n[:per_patch], rtol=0.1)
    assert len(np.unique(traj.patch[traj.press < per_patch])) == 1  # one patch's presses in turn
    if seconds >= LONG_PLAN_S:
        assert {k: getattr(plan, k) for k in ("ramp_s", "hold_s", "shear_s", "gap_s", "directions")} == {
            k: getattr(PROTOCOLS["full"], k) for k in ("ramp_s", "hold_s", "shear_s", "gap_s", "directions")}


@pytest.mark.parametrize("seconds", [120.0, 600.0])
def test_a_designed_plan_of_random_points_draws_its_cells_and_loads_at_random(seconds):
    """`design_protocol(..., points='random')`: the same presses, orientations and robot time as the
    designed plan, at as many distinct cells drawn at random in random order, each press of a short plan
    at a force level drawn at random (a long plan presses a patch's levels in turn, as the full protocol);
    stored in the run so it replays, and the other protocols' records keep their content."""
    even, drawn = design_protocol(seconds), design_protocol(seconds, points="random")
    assert drawn.duration_s == even.duration_s and drawn.orientations_deg == even.orientations_deg
    assert drawn.to_json()["order"] == "random"
    assert Protocol.model_validate(drawn.to_json()) == drawn
    rng = np.random.default_rng(3)
    cells = patch_cells(drawn, 0.0, rng)
    assert len({tuple(c) for c in cells}) == drawn.patches
    assert not np.array_equal(cells, patch_cells(drawn, 0.0, np.random.default_rng(4)))
    traj = build_trajectory(drawn, 0.0, np.random.default_rng(5))
    np.testing.assert_array_equal(_bins(traj.angles.astype(np.float32)), traj.cells[traj.patch])
    peaks = np.array([-traj.force[traj.press == p, 2].min() for p in range(traj.press.max() + 1)])
    levels = np.asarray(drawn.layers_n)[np.argmin(np.abs(peaks[:, None] / 0.95 - drawn.layers_n), axis=1)]
    if seconds < LONG_PLAN_S:
        assert drawn.layers_random and not np.array_equal(levels, np.resize(drawn.layers_n, len(levels)))
        assert len(set(levels.tolist())) > 1
    else:
        assert "layers_random" not in drawn.to_json()
        np.testing.assert_array_equal(levels, np.resize(drawn.layers_n, len(levels)))
    assert all("layers_random" not in p.to_json() for p in PROTOCOLS.values())
    with pytest.raises(ValueError, match="generator"):
        patch_cells(drawn, 0.0)
    with pytest.raises(ValueError, match="layer_cycle"):
        Protocol(name="x", layers_random=True)
    with pytest.raises(AnytipError, match="halton, random"):
        design_protocol(seconds, points="sobol")


def test_press_summary_counts_in_words():
    """The designed plan's summary, as `anytip calibrate --plan` prints it, for one place and for many."""
    assert press_summary(design_protocol(5.0)) == "1 press at 1 place, on 1 orientation"
    assert press_summary(design_protocol(30.0)) == "6 presses, one at each of 6 places, on 1 orientation"
    one_patch = Protocol(name="x", orientations_deg=(-45.0,), patches=1)  # every force level at a patch
    assert press_summary(one_patch) == "4 presses, 4 force levels at 1 place, on 1 orientation"
