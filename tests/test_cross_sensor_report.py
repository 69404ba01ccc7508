"""The cross-sensor report's arithmetic: ratios per distinct unit against its own reference,
intervals over units, and targets judged for the method validation units chose."""

from __future__ import annotations

import numpy as np
import pytest

from anytip.errors import AnytipError
from anytip.report.cross_sensor import (
    choice_margins,
    chosen_methods,
    mean_interval,
    paired_interval,
    paired_text,
    summary,
    targets,
    unit_ratios,
)


def row(method, unit, seed, force, angle=0.1, budget=100):
    return {"method": method, "unit": unit, "seed": seed, "calib_samples": budget, "calib_seconds": 1.0,
            "force_rmse_n": force, "angle_rmse_rad": angle, "n_train_units": 16}


def test_unit_ratios_average_seeds_before_dividing():
    rows = [row("per_unit", "A", 0, 1.0), row("per_unit", "A", 1, 3.0),
            row("m", "A", 0, 2.0), row("m", "A", 1, 2.0),
            row("per_unit", "B", 0, 2.0), row("m", "B", 0, 5.0)]
    r = unit_ratios(rows, "force_rmse_n")[("m", 100)]
    assert r == pytest.approx({"A": 2.0 / 2.0, "B": 2.5})  # A: mean 2 over mean 2, not mean(2, 2/3)


def test_a_row_without_its_own_reference_fails():
    rows = [row("per_unit", "A", 0, 1.0), row("m", "A", 1, 2.0)]
    with pytest.raises(AnytipError, match="unit A, seed 1 has no per_unit reference"):
        unit_ratios(rows, "force_rmse_n")


def test_the_interval_is_over_units_and_covers_the_mean():
    rng = np.random.default_rng(1)
    values = list(1.2 + 0.1 * rng.standard_normal(64))
    mean, lo, hi = mean_interval(values)
    assert lo < mean < hi and mean == pytest.approx(np.mean(values))
    assert hi - lo == pytest.approx(2 * 1.96 * np.std(values) / np.sqrt(64), rel=0.2)
    assert np.isnan(mean_interval([1.0])[1])


def test_targets_report_the_validation_choice_not_the_best_held_out_method():
    units = [f"U{k}" for k in range(8)]
    rows = [row("per_unit", u, 0, 1.0) for u in units]
    rows += [row("adapted:a", u, 0, 1.05, 0.105) for u in units]  # best on held-out units
    rows += [row("adapted:b", u, 0, 1.5, 0.15) for u in units]
    val = {"seed0": {"adapted:a": {"100": 0.9}, "adapted:b": {"100": 0.5}}}
    chosen = chosen_methods(val)
    assert chosen == {(100.0, None): "adapted:b"}
    table = targets(summary(rows), chosen)
    few_shot = table[1]
    assert "adapted:b" in few_shot[2] and few_shot[3].startswith("1.50x") and few_shot[-1] == "**not met**"
    assert table[0][2].startswith("n/a")  # no zero-shot budget was validated


def test_targets_are_judged_per_plan_strategy():
    units = [f"U{k}" for k in range(4)]
    rows = [row("per_unit", u, 0, 1.0) for u in units]
    for method, f in (("adapted:a@spread", 1.2), ("adapted:a@designed", 1.05), ("adapted:input_stats", 2.5)):
        rows += [dict(row(method, u, 0, f, 0.1 * f), budget_s=0 if "@" not in method else 120) for u in units]
    val = {"seed0": {"adapted:a@spread": {"120": 0.3}, "adapted:a@designed": {"120": 0.2},
                     "adapted:input_stats": {"0": 0.9}}}
    table = targets(summary(rows), chosen_methods(val), seconds=True)
    labels = [r[0] for r in table]
    assert labels[:3] == ["zero-shot (no labels)", "<= 120 s of robot time, `designed`",
                          "<= 120 s of robot time, `spread`"]
    assert table[0][-1] == "**not met**" and table[1][-1] == "met" and table[2][-1] == "**not met**"


def _val(losses: dict[str, list[float]]) -> dict[str, dict[str, dict[str, float]]]:
    """{seed: {method: {"120": loss}}} from each method's loss per seed."""
    n = len(next(iter(losses.values())))
    return {f"seed{k}": {m: {"120": v[k]} for m, v in losses.items()} for k in range(n)}


def test_a_choice_every_seed_agrees_on_is_resolved():
    val = _val({"a@cover": [1.0, 2.0, 1.5, 1.2], "b@informative": [1.2, 2.3, 1.8, 1.4],
                "c@cover": [3.0, 3.0, 3.0, 3.0]})
    m = choice_margins(val)[(120.0, "")]  # every plan strategy competes
    assert (m.method, m.runner_up) == ("a@cover", "b@informative")
    assert m.margin == pytest.approx(6.7 / 5.7 - 1)
    assert m.per_seed == pytest.approx([0.2, 0.15, 0.2, 1.4 / 1.2 - 1])
    assert 0 < m.lower < m.margin < m.upper and m.verdict == "resolved"


def test_a_choice_the_seeds_split_on_is_not_resolved():
    # the chosen method's mean is lower, but two of four seeds prefer the runner-up
    val = _val({"a@cover": [1.0, 1.0, 1.3, 1.3], "b@cover": [1.5, 1.5, 1.0, 1.0]})
    m = choice_margins(val)[(120.0, "")]
    assert m.method == "a@cover" and m.margin > 0
    assert m.lower < 0 < m.upper and m.verdict == "not resolved"


def test_only_methods_given_the_same_data_compete():
    val = _val({"a@cover": [1.0, 1.0], "b@cover": [2.0, 2.0], "a+use@cover": [0.5, 0.5]})
    margins = choice_margins(val, lambda method: "use" if "+use" in method else "plan")
    assert set(margins) == {(120.0, "plan")}  # the with-use method has no rival
    m = margins[(120.0, "plan")]
    assert (m.method, m.runner_up) == ("a@cover", "b@cover")
    assert np.isnan(m.lower) and m.verdict == "2 seeds: no interval"
    assert choice_margins(val)[(120.0, "")].runner_up == "a@cover"  # without families, with use beats all


def test_recorded_unit_losses_pair_the_choice_unit_by_unit():
    # two seeds' means give no interval; their four validation units, paired, do
    val = _val({"a@cover": [1.0, 2.0], "b@cover": [1.1, 2.3]})
    units = {"seed0": {"a@cover": {"120": {"U1": 0.9, "U2": 1.1}},
                       "b@cover": {"120": {"U1": 1.0, "U2": 1.2}}},
             "seed1": {"a@cover": {"120": {"U3": 1.9, "U4": 2.1}},
                       "b@cover": {"120": {"U3": 2.2, "U4": 2.4}}}}
    m = choice_margins(val, val_units=units)[(120.0, "")]
    assert (m.n, m.over) == (4, "validation units")
    assert m.margin == pytest.approx(3.4 / 3.0 - 1)  # the margin stays the ratio of the means
    assert 0 < m.lower < m.upper and m.verdict == "resolved"
    units["seed1"]["b@cover"]["120"] = {"U3": 1.5, "U4": 2.2}  # U3 now prefers b by far
    assert choice_margins(val, val_units=units)[(120.0, "")].verdict == "not resolved"


def test_a_unit_validating_in_several_seeds_is_one_pair():
    val = _val({"a@cover": [1.0, 1.0, 1.0], "b@cover": [1.2, 1.2, 1.2]})
    same = {"a@cover": {"120": {"U1": 1.0, "U2": 1.0}}, "b@cover": {"120": {"U1": 1.2, "U2": 1.1}}}
    m = choice_margins(val, val_units={f"seed{k}": same for k in range(3)})[(120.0, "")]
    assert (m.n, m.over) == (2, "validation units")  # six records, two units: no interval
    assert np.isnan(m.lower)


def test_paired_ratios_are_a_geometric_mean_and_their_text_its_figures():
    mean, lo, hi = paired_interval([0.5, 2.0, 0.5, 2.0])
    assert mean == pytest.approx(1.0) and lo < 1.0 < hi  # x0.5 and x2 cancel in log
    assert paired_interval([1.1] * 5) == pytest.approx((1.1, 1.1, 1.1))
    assert paired_text([0.9, 0.95, 1.0, 0.92]) == "{:.3f} [{:.3f}, {:.3f}]".format(
        *paired_interval([0.9, 0.95, 1.0, 0.92]))


def test_the_report_says_which_designed_runs_a_budget_reads():
    from anytip.pipelines.cross_sensor_options import Options
    from anytip.report.cross_sensor import _budget_text
    own = _budget_text(Options(budget_unit="seconds", plan_strategies=["cover", "designed"]), True)
    filled = _budget_text(Options(budget_unit="seconds", plan_strategies=["designed"], designed_scale=1.25),
                          True)
    assert "designed plan of each budget" in own and "1.25 times each budget" in filled
    assert "designed" not in _budget_text(Options(budget_unit="seconds", plan_strategies=["cover"]), True)
