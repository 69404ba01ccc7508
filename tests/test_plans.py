"""Calibration plans: whole presses, the budget's robot time honoured, test rows never touched."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.spatial import cKDTree

from anytip.data.arrays import FleetArrays, load_arrays
from anytip.data.calibration import calibration_stream
from anytip.data.catalog import RunRecord
from anytip.data.plans import (
    Budget,
    CodeInformation,
    RigTiming,
    find_presses,
    ordinary_use,
    plan_for,
    select_presses,
)
from anytip.data.registry import Registry
from anytip.data.simulated import simulate_into
from anytip.errors import AnytipError
from anytip.sensor.fleet import FleetConfig
from anytip.sensor.protocols import design_protocol, get_protocol

RATE = 200.0
PRESS_ROWS, GAP_ROWS, PRESSES_PER_RUN = 40, 100, 12


def record(k: int, orientation: float, rows: int) -> RunRecord:
    return RunRecord(f"run{k}", "U1", "pad", orientation, "measured", rows, 4, rows / RATE, None,
                     "0" * 64, "2024-01-01T00:00:00Z", f"runs/run{k}.h5", "2024-01-01T00:00:00Z")


def fleet(orientations=(0.0, -90.0), seed=0) -> FleetArrays:
    """One unit, one run per orientation; each run presses PRESSES_PER_RUN times at a fresh
    location and force level, with contact-free gaps (dropped, as load_arrays drops them)."""
    rng = np.random.default_rng(seed)
    parts = {k: [] for k in ("p", "f", "a", "r", "t")}
    runs = []
    for k, o in enumerate(orientations):
        n_run = PRESSES_PER_RUN * (PRESS_ROWS + GAP_ROWS)
        runs.append(record(k, o, n_run))
        for q in range(PRESSES_PER_RUN):
            first = q * (PRESS_ROWS + GAP_ROWS) + GAP_ROWS
            parts["t"].append((first + np.arange(PRESS_ROWS)) / RATE)
            parts["r"].append(np.full(PRESS_ROWS, k, np.int32))
            parts["p"].append(rng.normal(size=(PRESS_ROWS, 4)).astype(np.float32))
            force = np.zeros((PRESS_ROWS, 3), np.float32)
            force[:, 2] = -rng.uniform(2, 25)
            parts["f"].append(force)
            where = np.radians([rng.uniform(-45, 45), o + rng.uniform(-45, 45)])
            parts["a"].append(np.tile(where, (PRESS_ROWS, 1)).astype(np.float32))
    n = sum(len(t) for t in parts["t"])
    labels = np.concatenate([np.concatenate(parts["f"]), np.concatenate(parts["a"])], axis=1)
    return FleetArrays(np.concatenate(parts["p"]), labels, np.zeros(n, np.int32), np.concatenate(parts["r"]),
                       np.zeros(n, np.int16), np.zeros((len(runs), 4)), ["U1"], runs,
                       np.concatenate(parts["t"]))


def test_presses_are_the_contiguous_contact_segments_of_each_run():
    arrays = fleet()
    presses = find_presses(arrays, "U1")
    assert len(presses) == 2 * PRESSES_PER_RUN
    for k in range(len(presses)):
        rows = presses.rows_of(k)
        assert len(rows) == PRESS_ROWS and len(set(arrays.run[rows])) == 1
        assert np.allclose(np.diff(arrays.time[rows]), 1 / RATE)
    assert presses.duration_s == pytest.approx(np.full(len(presses), PRESS_ROWS / RATE))


def made_up_information(n_presses: int, criterion: str = "d", seed: int = 0, C: int = 2,
                        k: int = 3) -> CodeInformation:
    """Random positive semi-definite information (rank 2) per press and barometer, unit prior."""
    J = np.random.default_rng(seed).normal(size=(n_presses, C, k, 2))
    unit = np.tile(np.eye(k), (C, 1, 1))
    return CodeInformation(J @ J.swapaxes(-1, -2), unit, unit, criterion)


@pytest.mark.parametrize("strategy", ["spread", "cover", "random", "first", "informative",
                                      "cover_informative"])
@pytest.mark.parametrize("budget", [3.0, 12.0, 40.0, 90.0])
def test_a_plan_is_whole_presses_within_its_robot_time(strategy, budget):
    arrays, rig = fleet(), RigTiming(move_s=2.0, remount_s=30.0)
    presses = find_presses(arrays, "U1")
    information = made_up_information(len(presses))
    plan = select_presses(presses, budget, rig, strategy, seed=1, information=information)
    assert plan.calib_seconds <= budget + 1e-9
    assert plan.rows.size == plan.presses * PRESS_ROWS  # whole presses, each once
    whole = [set(presses.rows_of(k)) for k in range(len(presses))]
    assert all(s <= set(plan.rows) or not s & set(plan.rows) for s in whole)
    contact = plan.presses * PRESS_ROWS / RATE
    expected = contact + rig.move_s * plan.presses + rig.remount_s * max(len(plan.orientations) - 1, 0)
    assert plan.calib_seconds == pytest.approx(expected)
    assert plan.n_effective == pytest.approx(min(plan.rows.size, contact * rig.effective_hz))
    # a press at a time: the budget leaves no room for one more of the strategy's next choices
    assert budget - plan.calib_seconds < 2 * (PRESS_ROWS / RATE + rig.move_s) + rig.remount_s


def test_a_plan_changes_orientation_only_where_the_remount_fits():
    arrays, rig = fleet(), RigTiming(remount_s=30.0)
    presses = find_presses(arrays, "U1")
    assert len(select_presses(presses, 25.0, rig).orientations) == 1
    assert len(select_presses(presses, 120.0, rig).orientations) == 2


def test_spread_covers_the_target_space_better_than_the_first_presses():
    arrays = fleet(orientations=(0.0,))
    presses = find_presses(arrays, "U1")
    z = presses.summary

    def radius(plan_rows):
        chosen = [k for k in range(len(presses)) if presses.rows_of(k)[0] in set(plan_rows)]
        return max(np.min(np.linalg.norm(z[:, None] - z[None, chosen], axis=2), axis=1))

    spread, first = (select_presses(presses, 15.0, strategy=s) for s in ("spread", "first"))
    assert spread.presses == first.presses
    assert radius(spread.rows) < radius(first.rows)


def test_ordinary_use_is_whole_presses_from_every_orientation_up_to_its_contact_seconds():
    """Unlabeled ordinary use: random whole presses, contact seconds only (no moves or re-mounts
    charged), reaching both orientations where the first presses of the stream reach one."""
    arrays = fleet()
    presses = find_presses(arrays, "U1")
    press_s = PRESS_ROWS / RATE
    use = ordinary_use(presses, 10 * press_s, seed=3)
    rows = use.rows
    assert len(rows) == 10 * PRESS_ROWS  # ten presses fit: no rig time was charged
    assert use.calib_seconds == use.contact_seconds == pytest.approx(10 * press_s)
    whole = [set(presses.rows_of(k)) for k in range(len(presses))]
    assert all(w <= set(rows) or not w & set(rows) for w in whole)
    assert set(arrays.run[rows]) == {0, 1}
    assert np.array_equal(rows, ordinary_use(presses, 10 * press_s, seed=3).rows)
    assert not np.array_equal(np.sort(rows), np.sort(ordinary_use(presses, 10 * press_s, seed=4).rows))
    assert len(ordinary_use(presses, 0.0, seed=3).rows) == 0


def covering_radius(presses, plan) -> float:
    """The largest summary distance from a candidate press to the nearest press of `plan`."""
    z, rows = presses.summary, set(plan.rows)
    chosen = [k for k in range(len(presses)) if presses.rows_of(k)[0] in rows]
    return float(np.min(np.linalg.norm(z[:, None] - z[None, chosen], axis=2), axis=1).max())


@pytest.mark.parametrize("budget", [40.0, 70.0, 120.0])
def test_cover_reaches_the_target_space_at_least_as_well_as_spread(budget):
    presses = find_presses(fleet(orientations=(0.0, -45.0, -90.0)), "U1")
    cover, spread = (select_presses(presses, budget, strategy=s) for s in ("cover", "spread"))
    assert covering_radius(presses, cover) <= covering_radius(presses, spread) + 1e-9


def test_cover_pays_no_remount_for_an_orientation_that_reaches_nothing_new():
    """An orientation whose presses repeat the targets of the others' is not visited where the
    budget buys every press of the others (each press 0.2 s plus a 2 s move, one 30 s re-mount)."""
    arrays = fleet(orientations=(0.0, -90.0, -45.0))
    half = PRESSES_PER_RUN // 2 * PRESS_ROWS  # the third run repeats half of each other run's targets
    first, second = (np.flatnonzero(arrays.run == k) for k in (0, 1))
    arrays.labels[arrays.run == 2] = np.concatenate([arrays.labels[first[:half]],
                                                     arrays.labels[second[:half]]])
    presses = find_presses(arrays, "U1")
    for budget in (90.0, 100.0):
        plan = select_presses(presses, budget, strategy="cover")
        assert plan.orientations == (0.0, -90.0) or plan.orientations == (-90.0, 0.0)
        assert plan.presses == 2 * PRESSES_PER_RUN and covering_radius(presses, plan) == pytest.approx(0.0)


def test_a_press_that_touches_an_excluded_row_is_dropped_whole():
    arrays = fleet()
    exclude = np.zeros(arrays.n_rows, bool)
    exclude[[5, PRESS_ROWS + 7]] = True  # one row in each of the first two presses
    presses = find_presses(arrays, "U1", exclude)
    assert len(presses) == 2 * PRESSES_PER_RUN - 2
    plan = select_presses(presses, 1e6)
    assert not exclude[plan.rows].any() and plan.presses == len(presses)
    assert not np.isin(np.arange(2 * PRESS_ROWS), plan.rows).any()


def test_budgets_grow_plans_and_bad_budgets_are_refused():
    presses = find_presses(fleet(), "U1")
    sizes = [select_presses(presses, b).presses for b in (0, 5, 20, 60, 200, 1e4)]
    assert sizes[0] == 0 and sizes == sorted(sizes) and sizes[-1] == len(presses)
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(AnytipError, match="budget"):
            select_presses(presses, bad)
    with pytest.raises(AnytipError, match="move_s"):
        RigTiming(move_s=-1)
    with pytest.raises(AnytipError, match="strategy"):
        select_presses(presses, 10.0, strategy="best")


def test_presses_of_simulated_runs_are_the_protocol_presses(small_registry):
    arrays = load_arrays(small_registry, small_registry.list_runs())
    unit = arrays.units[0]
    presses = find_presses(arrays, unit)
    protocol = get_protocol("short")
    runs = {r.run_id for r in arrays.runs if r.unit == unit}
    assert len(presses) == len(runs) * protocol.patches * protocol.presses_per_patch
    plan = select_presses(presses, 60.0)
    assert 0 < plan.calib_seconds <= 60.0 and len(plan.orientations) >= 1


def test_designed_plans_take_the_presses_of_the_units_designed_runs(tmp_path):
    registry = Registry(tmp_path / "r")
    simulate_into(registry, FleetConfig(), 1, seed=2, protocols=("short", "plan30"))
    arrays = load_arrays(registry, registry.list_runs())
    unit = arrays.units[0]
    presses, stream = find_presses(arrays, unit), calibration_stream(arrays, unit, None)
    plan = plan_for(Budget(30.0, "seconds", "designed"), stream, presses)
    designed = design_protocol(30.0)
    assert plan.presses == designed.patches * len(designed.orientations_deg)
    assert {arrays.runs[k].protocol for k in np.unique(arrays.run[plan.rows])} == {"plan30"}
    assert 0.85 * 30 < plan.calib_seconds <= 30.0  # the plan uses its budget, moves included
    assert plan_for(Budget(60.0, "seconds", "designed"), stream, presses).presses == 0  # no plan60 runs


def test_a_designed_plan_may_read_a_longer_design_cut_at_its_budget(tmp_path):
    """`designed_s`: the budget's plan from the runs of a longer design, in recorded order up to the budget
    (a design that still fills it once a unit's test patches are left out); its own design is not read."""
    registry = Registry(tmp_path / "r")
    simulate_into(registry, FleetConfig(), 1, seed=2, protocols=("short", "plan30", "plan45"))
    arrays = load_arrays(registry, registry.list_runs())
    unit = arrays.units[0]
    presses, stream = find_presses(arrays, unit), calibration_stream(arrays, unit, None)
    budget = Budget(30.0, "seconds", "designed")
    own, longer = plan_for(budget, stream, presses), plan_for(budget, stream, presses, designed_s=45.0)
    assert {arrays.runs[k].protocol for k in np.unique(arrays.run[longer.rows])} == {"plan45"}
    assert 0.85 * 30 < longer.calib_seconds <= 30.0 and own.calib_seconds <= 30.0
    full = design_protocol(45.0)
    assert longer.presses < full.patches * len(full.orientations_deg)  # cut at the budget
    assert plan_for(budget, stream, presses, designed_s=60.0).presses == 0  # no plan60 runs


def test_a_designed_plans_presses_pay_their_recorded_leads_not_a_move_each():
    """Presses run in recorded order: each pays the time since its run's previous recorded press ended (a
    dropped one's time is not paid), the first of a run a move; selected presses pay a move each."""
    arrays = fleet()
    arrays.runs = [dataclasses.replace(r, protocol="plan60") for r in arrays.runs]
    gap, contact = GAP_ROWS / RATE, PRESS_ROWS / RATE
    dropped = np.zeros(len(arrays.run), bool)
    dropped[find_presses(arrays, "U1").rows_of(3)] = True  # the third press after the first, run 0
    presses = find_presses(arrays, "U1", exclude=dropped)
    assert np.isnan(presses.lead_s[[0, PRESSES_PER_RUN - 1]]).all()
    assert presses.lead_s[1:3] == pytest.approx([gap, gap]) and presses.lead_s[3] == pytest.approx(gap)
    plan = plan_for(Budget(60.0, "seconds", "designed"), None, presses)
    assert plan.presses == len(presses) == 2 * PRESSES_PER_RUN - 1
    own = len(presses) * contact + 2 * RigTiming().move_s + np.nansum(presses.lead_s) + RigTiming().remount_s
    assert plan.calib_seconds == pytest.approx(own) and own <= 60.0
    assert select_presses(presses, 60.0, strategy="first").presses < len(presses)  # a 2 s move each


def test_a_designed_calibrations_runs_are_a_plan_of_their_own_never_stream_test_or_training_rows(tmp_path):
    """Units with a designed calibration's runs beside others: their stream, their main rows (what units
    are trained and tested on) and the presses other strategies select from leave those runs out; the
    `designed` strategy's plan takes them alone. A unit with nothing but a designed calibration keeps it
    as its stream."""
    from anytip.train.shared_split import Roles, main_rows, prepare_seed

    registry = Registry(tmp_path / "r")
    simulate_into(registry, FleetConfig(), 4, seed=2, protocols=("short", "plan30"))
    arrays = load_arrays(registry, registry.list_runs())
    designed = np.array([arrays.runs[k].protocol == "plan30" for k in arrays.run])
    assert designed.any() and not (main_rows(arrays, None) & designed).any()
    for unit in arrays.units:
        assert not designed[calibration_stream(arrays, unit, None).rows].any()
    sd = prepare_seed(arrays, Roles(1, 1, None, 0.25, 0.1), None, False, seed=0)
    for ev in sd.evals.values():
        assert len(ev.test_rows) and not designed[ev.test_rows].any()
        cover = plan_for(Budget(30.0, "seconds", "cover"), ev.stream, ev.presses_for("cover"))
        plan = plan_for(Budget(30.0, "seconds", "designed"), ev.stream, ev.presses_for("designed"))
        assert cover.presses > 0 and not designed[cover.rows].any()
        assert plan.presses > 0 and designed[plan.rows].all()
        assert not np.isin(plan.rows, ev.test_rows).any()  # its presses in test patches are dropped whole
    alone = Registry(tmp_path / "alone")
    simulate_into(alone, FleetConfig(), 1, seed=3, protocols=("plan30",))
    only = load_arrays(alone, alone.list_runs())
    assert len(calibration_stream(only, only.units[0], None).rows) == only.n_rows


def test_a_test_sessions_runs_hold_a_units_test_rows_alone_and_nothing_else_reads_them(tmp_path):
    """Units with a test session (`retest`) beside their calibration runs: their test rows are that
    session's rows in their test patches, and no stream, plan, training or reference row comes from
    the session; its test patches stay out of every other run's rows that a plan or reference reads.
    With `test_rows: all_sessions` they are their main rows and the session's there, and only they move."""
    from anytip.train.shared_split import Roles, main_rows, prepare_seed

    registry = Registry(tmp_path / "r")
    simulate_into(registry, FleetConfig(), 4, seed=2, protocols=("short", "retest"))
    arrays = load_arrays(registry, registry.list_runs())
    session = np.array([arrays.runs[k].protocol == "retest" for k in arrays.run])
    assert session.any() and not (main_rows(arrays, None) & session).any()
    sd = prepare_seed(arrays, Roles(1, 1, None, 0.25, 0.1), None, False, seed=0)
    for ev in sd.evals.values():
        mine = np.flatnonzero(arrays.unit == arrays.units.index(ev.unit))
        assert len(ev.test_rows) and session[ev.test_rows].all()
        expected = mine[session[mine] & np.isin(arrays.patch[mine], ev.test_cells)]
        np.testing.assert_array_equal(ev.test_rows, expected)
        assert not session[ev.stream.rows].any() and not session[ev.presses.rows].any()
        assert not np.isin(arrays.patch[ev.presses.rows], ev.test_cells).any()
        cover = plan_for(Budget(30.0, "seconds", "cover"), ev.stream, ev.presses_for("cover"))
        assert cover.presses > 0 and not session[cover.rows].any()
    for unit in sd.split.train:
        assert not session[calibration_stream(arrays, unit, None).rows].any()
    both = prepare_seed(arrays, Roles(1, 1, None, 0.25, 0.1, test_rows="all_sessions"), None, False, seed=0)
    for unit, ev in both.evals.items():  # both sessions' rows at the same test patches, nothing else moves
        mine = np.flatnonzero(arrays.unit == arrays.units.index(unit))
        at = np.isin(arrays.patch[mine], ev.test_cells)
        main = mine[at & main_rows(arrays, None)[mine]]
        assert len(main) and np.array_equal(ev.test_rows, np.concatenate([main, sd.evals[unit].test_rows]))
        np.testing.assert_array_equal(ev.test_cells, sd.evals[unit].test_cells)
        np.testing.assert_array_equal(ev.stream.rows, sd.evals[unit].stream.rows)
        np.testing.assert_array_equal(ev.presses.rows, sd.evals[unit].presses.rows)


def test_a_labs_test_session_marked_in_the_registry_joins_its_test_rows_on_runs_from_the_format(tmp_path):
    """Rig runs made from the format spec alone (no in_contact, no temperature), each unit's later run
    marked `retest` in the registry: `test_rows: all_sessions` tests a unit on both runs' rows at its
    test patches, the default on the marked run's alone."""
    from anytip.train.shared_split import Roles, prepare_seed
    from run_factory import make_run

    registry = Registry(tmp_path / "r")
    runs = [make_run(f"LAB-{u}", 0.0, f"2024-05-0{k + 1}T12:00:00Z", n=600, seed=10 * u + k, source="rig",
                     optional=False) for u in range(4) for k in range(2)]
    for run in runs:
        run.force[run.time < 0.5] = 0.0  # the format's half second at rest before any contact
    registry.add_runs(runs)
    for u in range(4):
        registry.set_protocol(max(r.run_id for r in registry.list_runs(unit=f"LAB-{u}")), "retest")
    arrays = load_arrays(registry, registry.list_runs())
    session = np.array([arrays.runs[k].protocol == "retest" for k in arrays.run])
    alone, both = (prepare_seed(arrays, Roles(1, 1, None, 0.25, 0.1, test_rows=t), None, False, seed=0)
                   for t in ("test_session", "all_sessions"))
    for unit, ev in both.evals.items():
        mine = np.flatnonzero(arrays.unit == arrays.units.index(unit))
        at = mine[np.isin(arrays.patch[mine], ev.test_cells)]
        assert len(alone.evals[unit].test_rows) and session[alone.evals[unit].test_rows].all()
        np.testing.assert_array_equal(ev.test_rows, np.concatenate([at[~session[at]], at[session[at]]]))


def test_plans_work_on_runs_without_optional_data_written_from_the_format(tmp_path):
    """Runs made from the format spec alone, without in_contact or temperature: contact then comes
    from |F| >= 0.5 N, and presses (plans and ordinary use alike) from the rows it marks."""
    from run_factory import make_run

    registry = Registry(tmp_path / "r")
    runs = [make_run("LAB-1", o, f"2024-05-0{k + 1}T12:00:00Z", n=600, seed=k, optional=False)
            for k, o in enumerate((0.0, -90.0))]
    for run in runs:
        g = np.random.default_rng(0)
        run.force[:] = 0.0
        for start in range(50, 600, 100):  # six presses of 30 rows per run, rest between them
            run.force[start:start + 30, 2] = -g.uniform(2, 20)
    registry.add_runs(runs)
    arrays = load_arrays(registry, registry.list_runs())
    presses = find_presses(arrays, "LAB-1")
    assert len(presses) == 12 and all(len(presses.rows_of(k)) == 30 for k in range(12))
    plan = select_presses(presses, 20.0, RigTiming(move_s=2.0, remount_s=30.0))
    assert plan.calib_seconds <= 20.0 and plan.presses >= 2 and len(plan.orientations) == 1
    assert len(ordinary_use(presses, 1e6, seed=0).rows) == 12 * 30  # every press of both runs, no rig time
    assert len(ordinary_use(presses, float(presses.duration_s.min()), seed=0).rows) == 30  # one whole press


def test_a_labs_runs_marked_as_a_longer_design_serve_a_scaled_designed_budget(tmp_path):
    """Runs made from the format spec alone, without optional data, one per unit marked `plan150` in the
    registry: the `designed` strategy at 120 s with the design of 150 s (`designed_s`,
    `options.designed_scale` 1.25) takes that run's presses alone, within 120 s; without the scale it finds
    no plan120 run, and the benchmark names what is missing."""
    from anytip.pipelines.cross_sensor_jobs import missing_designs
    from anytip.pipelines.cross_sensor_options import Options
    from run_factory import make_run

    registry = Registry(tmp_path / "r")
    runs = [make_run("LAB-1", 0.0, f"2024-05-0{k + 1}T12:00:00Z", n=600, seed=k, optional=False)
            for k in (0, 1)]
    for run in runs:
        run.force[:] = 0.0
        for start in range(50, 600, 100):  # six presses of 30 rows, rest between them
            run.force[start:start + 30, 2] = -10.0
    registry.add_runs(runs)
    registry.set_protocol(max(r.run_id for r in registry.list_runs(unit="LAB-1")), "plan150")
    arrays = load_arrays(registry, registry.list_runs())
    presses, budget = find_presses(arrays, "LAB-1"), Budget(120.0, "seconds", "designed")
    plan = plan_for(budget, None, presses, designed_s=150.0)
    assert plan.presses == 6 and 0 < plan.calib_seconds <= 120.0
    assert {arrays.runs[k].protocol for k in np.unique(arrays.run[plan.rows])} == {"plan150"}
    assert plan_for(budget, None, presses).presses == 0  # no plan120 run
    opts = dict(budget_unit="seconds", budgets=[0, 120], plan_strategies=["designed"])
    assert missing_designs(arrays, Options(**opts, designed_scale=1.25)) == []
    assert missing_designs(arrays, Options(**opts)) == ["plan120"]


def test_press_folds_hold_out_every_press_exactly_once():
    """split_presses(k, fold) for fold 0..k-1: each fold's check rows are whole presses, fitting
    and check rows partition the plan, and together the folds hold out every row once."""
    arrays = fleet()
    rig = RigTiming(move_s=2.0, remount_s=30.0)
    plan = select_presses(find_presses(arrays, "U1"), 90.0, rig, "spread", 1)
    assert plan.presses >= 4
    checks = []
    for fold in range(3):
        fit, check = plan.split_presses(3, fold)
        assert sorted(np.concatenate([fit, check])) == sorted(plan.rows)
        assert len(check) % PRESS_ROWS == 0 and len(check) > 0
        checks.append(check)
    assert sorted(np.concatenate(checks)) == sorted(plan.rows)
    assert np.array_equal(plan.split_presses(3)[1], checks[0])  # fold 0 is the own check's split
    fit, check = plan.split_presses(plan.presses + 1, plan.presses)  # a fold past the last press
    assert len(check) == 0 and np.array_equal(fit, plan.rows)


def test_a_plan_without_a_folds_presses_keeps_whole_presses_and_their_bounds():
    """without_presses(k, fold): the smaller plan holds split_presses' fitting rows, press by press
    (its bounds cut them where the whole plan's did), and its effective count shrinks with its rows."""
    arrays = fleet()
    rig = RigTiming(move_s=2.0, remount_s=30.0)
    plan = select_presses(find_presses(arrays, "U1"), 90.0, rig, "spread", 1)
    smaller, check = plan.without_presses(3, 1)
    assert np.array_equal(smaller.rows, plan.split_presses(3, 1)[0])
    assert np.array_equal(check, plan.split_presses(3, 1)[1])
    assert smaller.presses == plan.presses - len(range(1, plan.presses, 3))
    whole = {tuple(plan.rows[a:b]) for a, b in zip(plan.bounds[:-1], plan.bounds[1:], strict=True)}
    kept = [tuple(smaller.rows[a:b]) for a, b in zip(smaller.bounds[:-1], smaller.bounds[1:], strict=True)]
    assert len(kept) == smaller.presses and set(kept) <= whole
    assert smaller.n_effective == pytest.approx(plan.n_effective * len(smaller.rows) / len(plan.rows))
    assert smaller.calib_seconds == plan.calib_seconds  # the rig spent the whole plan's time


def axis_information(axes: list[int], strength: list[float], region: tuple[float, float],
                     criterion: str) -> CodeInformation:
    """One barometer, a code of 2: press p tells code dimension axes[p] with strength[p]."""
    per_press = np.zeros((len(axes), 1, 2, 2))
    for p, (a, s) in enumerate(zip(axes, strength, strict=True)):
        per_press[p, 0, a, a] = s
    return CodeInformation(per_press, np.eye(2)[None] * 0.1, np.diag(region)[None], criterion)


def test_informative_plans_pick_presses_for_the_code_directions_left_open():
    arrays = fleet(orientations=(0.0,))
    presses = find_presses(arrays, "U1")
    cost = PRESS_ROWS / RATE + RigTiming().move_s  # one press and its move
    axes = [0] * 6 + [1] * 6  # the first six tell dimension 0 a little better than the rest tell 1
    strength = [10.0] * 6 + [8.0] * 6
    for crit, region, expected in (("d", (1.0, 1.0), {0, 1}), ("v", (1.0, 1.0), {0, 1}),
                                   ("v", (0.0, 1.0), {1})):
        info = axis_information(axes, strength, region, crit)
        plan = select_presses(presses, 2 * cost, strategy="informative", information=info)
        chosen = [k for k in range(len(presses)) if presses.rows_of(k)[0] in set(plan.rows)]
        assert plan.presses == 2 and {axes[k] for k in chosen} == expected, (crit, region)


def test_informative_plans_pay_a_remount_only_for_information_worth_it():
    arrays, rig = fleet(), RigTiming(remount_s=5.0)  # 20 s: 9 presses of one orientation, or 6 of two
    presses = find_presses(arrays, "U1")
    other = presses.orientation_deg != presses.orientation_deg[0]
    axes = list(other.astype(int))  # the second orientation alone tells code dimension 1
    info = axis_information(axes, [5.0] * len(presses), (1.0, 1.0), "d")
    plan = select_presses(presses, 20.0, rig, "informative", information=info)
    assert len(plan.orientations) == 2 and plan.presses == 6 and plan.calib_seconds <= 20.0
    same = axis_information([0] * len(presses), [5.0] * len(presses), (1.0, 1.0), "d")
    plan = select_presses(presses, 20.0, rig, "informative", information=same)
    assert len(plan.orientations) == 1 and plan.presses == 9


def test_cover_informative_keeps_covers_cells_and_takes_each_cells_most_informative_press():
    arrays, rig = fleet(), RigTiming(remount_s=30.0)
    presses = find_presses(arrays, "U1")
    information = made_up_information(len(presses), "v", seed=3)
    cover = select_presses(presses, 40.0, rig, "cover")
    mixed = select_presses(presses, 40.0, rig, "cover_informative", information=information)
    assert mixed.presses == cover.presses and mixed.orientations == cover.orientations
    assert mixed.calib_seconds <= 40.0

    def chosen(plan):
        return [k for k in range(len(presses)) if presses.rows_of(k)[0] in set(plan.rows)]

    def value(plan):
        return information.value(information.prior + information.per_press[chosen(plan)].sum(0))

    assert value(mixed) > value(cover)  # it exchanged presses, and only for the better
    cells = cKDTree(presses.summary[chosen(cover)]).query(presses.summary[chosen(mixed)])[1]
    assert sorted(cells) == list(range(cover.presses))  # one press in each of cover's cells


def test_informative_plans_name_what_they_lack():
    presses = find_presses(fleet(), "U1")
    with pytest.raises(AnytipError, match="response method"):
        select_presses(presses, 40.0, strategy="informative")
    with pytest.raises(AnytipError, match="information for 3 presses"):
        select_presses(presses, 40.0, strategy="informative", information=made_up_information(3))
    with pytest.raises(AnytipError, match="criterion 'x'"):
        select_presses(presses, 40.0, strategy="informative",
                       information=made_up_information(len(presses), "x"))


def test_a_factor_units_test_patches_do_not_depend_on_how_many_units_are_held_out(tmp_path, monkeypatch):
    """The same validation and factor units beside one or two held-out units: their test cells, and
    so their plans and what they teach the fleet factor, are the same; the held-out unit they share
    keeps its cells too."""
    import anytip.train.shared_split as shared_split
    from anytip.data.splits import UnitSplit

    registry = Registry(tmp_path / "r")
    simulate_into(registry, FleetConfig(), 5, seed=2, protocols=("short", "quick"))
    arrays = load_arrays(registry, registry.list_runs())
    a, b, c, d, e = arrays.units
    cells = []
    for held_out in ((d,), (d, e)):
        split = UnitSplit((a,), (b,), held_out, (c,))
        monkeypatch.setattr(shared_split, "split_units", lambda *_, s=split, **__: s)
        sd = shared_split.prepare_seed(arrays, shared_split.Roles(1, 1, None, 0.25, 0.1), None, False, seed=0)
        cells.append({u: set(ev.test_cells.tolist()) for u, ev in sd.evals.items()})
    for unit in (b, c, d):
        assert cells[0][unit] == cells[1][unit] and cells[0][unit]
    assert set(cells[1]) == {b, c, d, e}
