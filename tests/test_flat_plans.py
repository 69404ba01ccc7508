"""The flat designs' designed calibration (`sensor.flat.design_plan`): its budget, its spread over the
design's pressed region and load range, the simulator's runs of it as the benchmark prices them, and the
stage waypoints `anytip calibrate --plan SECONDS --sensor-model NAME` writes."""

import csv
import io

import numpy as np
import pytest

from anytip.cli import main
from anytip.data.arrays import load_arrays
from anytip.data.plans import RigTiming, designed_plan_csv, find_presses, select_presses
from anytip.data.registry import Registry
from anytip.data.simulated import regenerate, simulate_flat_into
from anytip.errors import AnytipError
from anytip.sensor import flat

DESIGNS = sorted(flat.DESIGNS)


@pytest.mark.parametrize("model", DESIGNS)
@pytest.mark.parametrize("seconds, move_s", [(30.0, 2.0), (120.0, 2.0), (120.0, 0.5), (600.0, 2.0)])
def test_a_designed_plan_fills_its_budget_with_whole_presses(model, seconds, move_s):
    plan = flat.design_plan(flat.get_design(model), seconds, move_s)
    assert plan.name == f"plan{seconds:g}" and plan.duration_s <= seconds < plan.duration_s + plan.press_s
    assert plan.press_s == pytest.approx(move_s + flat.LOAD_S + flat.HOLD_S + flat.UNLOAD_S)


@pytest.mark.parametrize("model", DESIGNS)
def test_a_designed_plan_spreads_over_the_region_and_the_load_range(model):
    """Every fifth of each pressed axis and of the load range holds a press of a 120 s plan, and on the
    pad every quarter of shear directions; no two presses share a place."""
    design = flat.get_design(model)
    plan = flat.design_plan(design, 120.0)
    x0, x1, y0, y1 = design.region_m
    axes = [(plan.where[:, 0] - x0) / (x1 - x0)] + ([(plan.where[:, 1] - y0) / (y1 - y0)] if y1 > y0 else [])
    axes.append((plan.level - 0.15) / 0.85)
    for values in axes:
        assert values.min() >= 0 and values.max() <= 1
        assert len(np.unique(np.minimum((values * 5).astype(int), 4))) == 5
    assert len(np.unique(plan.where, axis=0)) == len(plan.level)
    ratio = np.hypot(*plan.shear.T)
    if design.shear_ratio > 0:
        assert ratio.max() <= design.shear_ratio
        quarter = (np.arctan2(plan.shear[:, 1], plan.shear[:, 0]) // (np.pi / 2)).astype(int)
        assert len(np.unique(quarter)) == 4
    else:
        assert not ratio.any()


def test_random_plan_points_cover_the_same_ranges_without_the_design():
    """`points='random'` draws as many points over the same region, load and shear ranges, independently:
    not the Halton design's points, and less even over the region (a wider largest gap)."""
    design = flat.get_design("pad-16baro")
    halton, drawn = (flat.design_plan(design, 120.0, seed=3, points=p) for p in ("halton", "random"))
    assert len(drawn.level) == len(halton.level)
    x0, x1, y0, y1 = design.region_m
    assert np.all((drawn.where >= [x0, y0]) & (drawn.where <= [x1, y1]))
    assert drawn.level.min() >= 0.15 and drawn.level.max() <= 1.0
    assert np.all(np.hypot(*drawn.shear.T) <= design.shear_ratio)
    assert not np.allclose(drawn.where, halton.where)

    def largest_gap(level: np.ndarray) -> float:  # over the load range [0.15, 1], its ends included
        return float(np.diff(np.sort(np.concatenate([[0.15, 1.0], level]))).max())

    assert largest_gap(drawn.level) > largest_gap(halton.level)
    with pytest.raises(AnytipError, match="points are one of halton, random"):
        flat.design_plan(design, 120.0, points="grid")


def test_a_designed_plan_is_its_seeds_and_refuses_what_holds_no_press():
    design = flat.get_design("pad-16baro")
    a, b, c = (flat.design_plan(design, 60.0, seed=s) for s in (0, 0, 1))
    assert np.array_equal(a.where, b.where) and not np.array_equal(a.where, c.where)
    refused = [(2.0, 2.0, "holds no press"), (0.0, 2.0, "> 0 s"), (60.0, 0.0, "move time")]
    for seconds, move_s, match in refused:
        with pytest.raises(AnytipError, match=match):
            flat.design_plan(design, seconds, move_s)


@pytest.mark.parametrize("model, move_s, points", [(m, 2.0, "halton") for m in DESIGNS]
                         + [("edge-4baro", 0.4, "halton"), ("pad-16baro", 0.4, "random")])
def test_simulated_plan_runs_replay_and_their_presses_fit_the_budget(model, move_s, points, tmp_path):
    """A unit's `plan40` run (`anytip data simulate --protocols plan40 [--move-s S] [--plan-points P]`)
    holds the plan's presses, each found whole by `find_presses` and led by the rig's move; priced as
    the benchmark prices a designed plan (each press's contact plus its recorded lead) it fits its
    40 s, and it replays bit for bit from its record."""
    reg = Registry(tmp_path / "reg")
    simulate_flat_into(reg, model, 1, 7, ("plan40",), move_s=move_s, points=points)
    (record,) = reg.list_runs()
    assert record.protocol == "plan40"
    run = reg.open_run(record.run_id)
    assert regenerate(run.simulator).content_hash() == run.content_hash()
    arrays = load_arrays(reg, [record])
    presses = find_presses(arrays, record.unit)
    n = len(flat.design_plan(flat.get_design(model), 40.0, move_s).level)
    assert len(presses) == n
    assert np.all(presses.lead_s[1:] >= move_s) and np.all(presses.lead_s[1:] < move_s + 0.4)
    plan = select_presses(presses, 40.0, RigTiming(move_s), "first", recorded_moves=True)
    assert plan.presses == n and plan.calib_seconds <= 40.0


@pytest.mark.parametrize("model, command", [("edge-4baro", ("depth_m",)),
                                            ("pad-16baro", ("fx_n", "fy_n", "fz_n"))])
def test_the_plan_csv_commands_each_press_within_the_design(model, command):
    """Four waypoints a press (load starts, load reached, hold ends, unloaded) at rising times, the
    pressed point inside the region, the command zero between presses and within the design's
    maximum depth, or force and shear, at its peak."""
    design = flat.get_design(model)
    text, seconds, what = designed_plan_csv(120.0, RigTiming(move_s=2.0), seed=3, sensor_model=model)
    rows = list(csv.DictReader(io.StringIO(text)))
    assert tuple(rows[0]) == ("time_s", "x_m", "y_m", *command)
    n = len(flat.design_plan(design, 120.0, seed=3).level)
    assert len(rows) == 4 * n and what.startswith(f"{n} presses") and seconds <= 120.0
    table = np.array([[float(r[k]) for k in rows[0]] for r in rows])
    assert np.all(np.diff(table[:, 0]) > 0) and table[0, 0] == pytest.approx(2.0)
    x0, x1, y0, y1 = design.region_m
    assert np.all((x0 <= table[:, 1]) & (table[:, 1] <= x1) & (y0 <= table[:, 2]) & (table[:, 2] <= y1))
    ends, peaks = table[0::4, 3:], table[1::4, 3:]
    assert not ends.any() and not table[3::4, 3:].any() and np.array_equal(peaks, table[2::4, 3:])
    if design.max_depth_m is not None:
        assert np.all((0 < peaks[:, 0]) & (peaks[:, 0] <= design.max_depth_m + 1e-6))
    else:
        assert np.all((-design.max_force_n - 1e-6 <= peaks[:, 2]) & (peaks[:, 2] < 0))
        shear = np.hypot(peaks[:, 0], peaks[:, 1])
        assert np.all(shear <= design.shear_ratio * -peaks[:, 2] + 1e-5)


def test_calibrate_plan_writes_a_flat_designs_waypoints_and_names_what_it_refuses(tmp_path, capsys):
    out = tmp_path / "edge.csv"
    assert main(["calibrate", "--plan", "60", "--sensor-model", "edge-4baro", "--move-s", "1", "--out",
                 str(out)]) == 0
    printed = capsys.readouterr().out
    n = len(flat.design_plan(flat.get_design("edge-4baro"), 60.0, 1.0).level)
    assert f"{n} presses, one at each of {n} places, on 1 orientation" in printed and "moves 1 s" in printed
    assert out.read_text().startswith("time_s,x_m,y_m,depth_m\n")
    drawn = tmp_path / "random.csv"
    assert main(["calibrate", "--plan", "60", "--sensor-model", "edge-4baro", "--plan-points", "random",
                 "--out", str(drawn)]) == 0
    first = np.array([float(v) for v in drawn.read_text().splitlines()[1].split(",")])
    random_plan = flat.design_plan(flat.get_design("edge-4baro"), 60.0, points="random")
    assert first[1] == pytest.approx(random_plan.where[0, 0], abs=1e-6)
    by_default, halton = tmp_path / "default.csv", tmp_path / "halton.csv"  # random points by default
    for path, extra in ((by_default, []), (halton, ["--plan-points", "halton"])):
        assert main(["calibrate", "--plan", "60", "--sensor-model", "edge-4baro", *extra,
                     "--out", str(path)]) == 0
    assert by_default.read_text() == drawn.read_text() != halton.read_text()
    refused = [(["--plan", "60", "--sensor-model", "pad-16baro", "--remount-s", "10"], "no re-mount"),
               (["--plan", "60", "--sensor-model", "fingertip"], "plans are designed for"),
               (["--unit", "U", "--sensor-model", "edge-4baro"], "--sensor-model is for --plan"),
               (["--unit", "U", "--plan-points", "random"], "--plan-points is for --plan")]
    for args, message in refused:
        assert main(["calibrate", *args, "--out", str(tmp_path / "x.csv")]) != 0
        assert message in capsys.readouterr().err


def test_data_simulate_runs_a_flat_designs_plan_and_names_an_unknown_protocol(tmp_path, capsys):
    reg = tmp_path / "reg"
    base = ["data", "simulate", "--registry", str(reg), "--units", "1", "--sensor-model", "pad-16baro"]
    assert main([*base, "--protocols", "plan8"]) == 0
    assert [r.protocol for r in Registry(reg).list_runs()] == ["plan8"]
    assert main([*base, "--protocols", "sweep"]) != 0
    assert "runs the protocols ['full', 'quick', 'short'] and plan<seconds>" in capsys.readouterr().err


def test_data_simulate_times_a_designed_plans_moves_and_refuses_a_move_without_one(tmp_path, capsys):
    """`--move-s` sets the rig's move before each press of a designed plan, on the fingertip as on a
    flat design (each press's recorded lead is the move), and is refused where no protocol is designed
    or the time is not a duration."""
    for model, move_s in (("edge-4baro", 0.4), ("fingertip-8baro-r10", 1.0)):
        reg = tmp_path / model
        args = ["data", "simulate", "--registry", str(reg), "--units", "1", "--sensor-model", model,
                "--protocols", "plan20", "--move-s", str(move_s)]
        assert main(args) == 0
        records = Registry(reg).list_runs()
        assert {r.protocol for r in records} == {"plan20"}
        presses = find_presses(load_arrays(Registry(reg), records), records[0].unit)
        leads = presses.lead_s[~np.isnan(presses.lead_s)]
        assert len(leads) > 0 and np.all(leads >= move_s) and np.all(leads < move_s + 0.5)
    base = ["data", "simulate", "--registry", str(tmp_path / "no"), "--units", "1"]
    not_a_duration = "--move-s must be a finite number of seconds > 0"
    refused = [(["--protocols", "full", "--move-s", "0.4"], "--move-s times the moves of a designed plan"),
               (["--protocols", "plan20", "--move-s", "nan"], not_a_duration),
               (["--protocols", "plan20", "--move-s", "0"], not_a_duration),
               (["--protocols", "full", "--plan-points", "random"], "--plan-points chooses the points of a "
                                                                     "designed plan")]
    for args, message in refused:
        assert main([*base, *args]) != 0
        assert message in capsys.readouterr().err
