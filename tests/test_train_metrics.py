import math

import numpy as np
import pytest
import torch

from anytip.errors import AnytipError
from anytip.models import BatchedMLP, MLPConfig, Scaler
from anytip.train import (
    FAST,
    PAPER,
    TrainRecipe,
    angle_rmse,
    evaluate,
    force_rmse,
    force_rmse_per_axis,
    get_recipe,
    lr_at,
    rmse_per_output,
    time_to_target,
)
from anytip.train.metrics import binned_rmse, ratio_fields, region_rmse, rmse, scores
from anytip.train.timing import select_units


def test_force_and_angle_rmse_definitions():
    target = torch.zeros(4, 5)
    pred = torch.zeros(4, 5)
    pred[:, 0] = 3.0  # Fx off by 3 N on every row, Fy, Fz exact
    pred[:2, 3] = 0.2  # theta off by 0.2 rad on half the rows
    assert float(force_rmse(pred, target)) == pytest.approx(math.sqrt(9 / 3))
    assert force_rmse_per_axis(pred, target).tolist() == pytest.approx([3.0, 0.0, 0.0])
    assert float(angle_rmse(pred, target)) == pytest.approx(math.sqrt(0.04 / 2 / 2))
    assert rmse_per_output(pred, target).shape == (5,)


def test_metrics_ignore_masked_rows_per_unit():
    pred, target = torch.zeros(2, 6, 5), torch.zeros(2, 6, 5)
    pred[1, 3:] = 100.0  # padding rows of unit 1
    pred[1, :3, 2] = 2.0
    mask = torch.arange(6) < torch.tensor([6, 3])[:, None]
    assert force_rmse(pred, target, mask).tolist() == pytest.approx([0.0, math.sqrt(4 / 3)])


def test_evaluate_on_lists_equals_padded():
    model = BatchedMLP(2, MLPConfig(), seed=0)
    ins, outs = Scaler(torch.zeros(2, 1, 8), torch.full((2, 1, 8), 1e3)), Scaler.identity(2, 5)
    xs, ys = [torch.randn(7, 8) * 1e3, torch.randn(4, 8) * 1e3], [torch.randn(7, 5), torch.randn(4, 5)]
    a = evaluate(model, ins, outs, xs, ys)
    X = torch.zeros(2, 7, 8)
    Y = torch.zeros(2, 7, 5)
    X[0], Y[0], X[1, :4], Y[1, :4] = xs[0], ys[0], xs[1], ys[1]
    b = evaluate(model, ins, outs, X, Y, torch.tensor([7, 4]))
    for k in ("force_rmse", "angle_rmse", "rmse", "loss"):
        torch.testing.assert_close(a[k], b[k])
    with torch.no_grad():
        pred1 = model.to_sequential(1)(xs[1] / 1e3)
    assert float(a["force_rmse"][1]) == pytest.approx(float(force_rmse(pred1, ys[1])), rel=1e-5)


def test_recipes_and_schedules():
    assert get_recipe("paper") == PAPER and PAPER.batch_size == 10 and PAPER.epochs == 10
    with pytest.raises(AnytipError, match="known: \\['fast', 'paper'\\]"):
        get_recipe("slow")
    with pytest.raises(ValueError, match="extra"):
        TrainRecipe(name="x", momentum=0.9)
    assert lr_at(0, 100, PAPER) == lr_at(99, 100, PAPER) == 1e-3
    r = TrainRecipe(name="r", lr=1.0, schedule="onecycle", warmup_frac=0.2, final_lr_frac=0.01)
    lrs = [lr_at(s, 100, r) for s in range(100)]
    assert lrs[0] < 0.1 and lrs[19] == pytest.approx(1.0) and lrs[-1] == pytest.approx(0.01)
    assert max(lrs) == pytest.approx(1.0)
    c = r.model_copy(update={"schedule": "cosine"})
    assert lr_at(0, 100, c) == pytest.approx(0.05) and lr_at(99, 100, c) == pytest.approx(0.01)
    assert FAST.batch_size > PAPER.batch_size


def test_time_to_target():
    history = [{"elapsed_s": 1.0, "val_force_rmse": [2.0, 1.0]},
               {"elapsed_s": 2.0, "val_force_rmse": [1.0, 1.2]},
               {"elapsed_s": 3.0, "val_force_rmse": [0.9, 0.9]}]
    assert time_to_target(history, 1.5) == 1.0
    assert time_to_target(history, 1.5, reduce="max") == 2.0
    assert time_to_target(history, 1.0, tol=0.05, reduce="max") == 3.0
    assert time_to_target(history, 0.5) is None
    assert time_to_target([{"elapsed_s": 4.0, "val_force_rmse": 0.3}], 0.3) == 4.0
    assert time_to_target(history, [1.0, 1.2]) == 2.0  # one target per unit: all must be there
    assert time_to_target(select_units(history, [1]), [1.0]) == 1.0


def test_binned_rmse_is_the_rmse_of_each_bin_and_nan_where_empty():
    rng = np.random.default_rng(0)
    pred, target = rng.normal(size=(200, 5)), rng.normal(size=(200, 5))
    err2 = ((pred - target) ** 2).mean(axis=1)
    bins = rng.integers(-1, 4, size=200)  # -1: outside every bin
    out = binned_rmse(err2, bins, 5)
    for b in range(4):
        assert out[b] == pytest.approx(rmse(pred[bins == b], target[bins == b]), rel=1e-12)
    assert np.isnan(out[4])


def test_region_rmse_puts_each_row_in_its_cell_of_the_sensing_region():
    angles = np.radians([[-44.0, -134.0], [-44.0, -134.0], [44.0, 44.0], [60.0, 0.0]])
    grid, t_edges, p_edges = region_rmse(angles, np.array([1.0, 9.0, 4.0, 100.0]), cell_deg=7.5)
    assert grid.shape == (len(t_edges) - 1, len(p_edges) - 1) == (12, 24)
    assert grid[0, 0] == pytest.approx(np.sqrt(5.0)) and grid[-1, -1] == pytest.approx(2.0)
    assert np.isfinite(grid).sum() == 2  # theta 60 deg lies outside the region


def test_ratio_fields_divide_each_targets_rmse_by_the_reference():
    """The fingertip's targets give `force_ratio` and `angle_ratio`; each is the model's RMSE over the
    reference's on the same rows."""
    target = np.zeros((4, 5))
    ours, ref = target.copy(), target.copy()
    ours[:, 0], ref[:, 0] = 2.0, 1.0  # force: 2 N against 1 N on fx
    ours[:, 3], ref[:, 3] = 0.1, 0.4  # angle: 0.1 against 0.4 rad on theta
    ratios = ratio_fields(scores(ours, target), scores(ref, target))
    assert ratios == pytest.approx({"force_ratio": 2.0, "angle_ratio": 0.25})
