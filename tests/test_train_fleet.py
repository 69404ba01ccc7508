import pytest
import torch

from anytip.models import MLPConfig, load_models
from anytip.train import FAST, PAPER, FleetBatchData, TrainRecipe, evaluate, train_fleet
from anytip.train.synthetic import synthetic_fleet

QUICK = TrainRecipe(name="quick", lr=1e-2, batch_size=64, epochs=6, schedule="onecycle",
                    warmup_frac=0.2, final_lr_frac=1e-2, evals_per_epoch=2)


@pytest.fixture(scope="module")
def data():
    return synthetic_fleet(n_units=3, n_rows=2000, seed=0)


@pytest.fixture(scope="module")
def fit(data):
    return train_fleet(data, recipe=QUICK, seed=0)


def test_training_reduces_loss_and_reaches_a_reasonable_rmse(data, fit):
    first, last = fit.history[0], fit.history[-1]
    assert len(fit.history) == 12 and last["epoch"] == 6
    assert all(b < a / 3 for a, b in zip(first["train_loss"], last["train_loss"], strict=True))
    val = evaluate(fit.model, fit.in_scaler, fit.out_scaler, data.X_val, data.Y_val, data.n_val)
    spread = data.Y_val[..., :3].std()  # a constant guess scores about this
    assert (val["force_rmse"] < 0.25 * spread).all()
    assert (val["angle_rmse"] < 0.2).all()
    assert val["loss"].tolist() == pytest.approx([min(r["val_loss"][u] for r in fit.history)
                                                  for u in range(3)])  # best kept per unit


def test_same_seed_gives_identical_weights(data, fit):
    again = train_fleet(data, recipe=QUICK, seed=0)
    for p, q in zip(fit.model.parameters(), again.model.parameters(), strict=True):
        assert torch.equal(p, q)
    other = train_fleet(data, recipe=QUICK, seed=1)
    assert not torch.equal(fit.model.weights[0], other.model.weights[0])


def test_units_are_independent(data):
    """Other units' data, and when they stop, change nothing of unit 0's trained weights."""
    recipe = QUICK.model_copy(update={"patience": 2, "epochs": 8})
    changed = data.unit(1)
    changed.X_train = changed.X_train.flip(0) * 2 + 1e3
    changed.Y_train = torch.randn_like(changed.Y_train)
    other = FleetBatchData.from_units([data.unit(0), changed, data.unit(2)])
    a, b = train_fleet(data, recipe=recipe, seed=5), train_fleet(other, recipe=recipe, seed=5)
    for p, q in zip(a.model.parameters(), b.model.parameters(), strict=True):
        assert torch.equal(p[0], q[0]) and torch.equal(p[2], q[2])
        assert not torch.equal(p[1], q[1])
    assert torch.equal(a.in_scaler.mean[0], b.in_scaler.mean[0])


def test_fleet_of_one_matches_the_fleet(data):
    """Unit 0 trained alone ends where it ends inside a fleet of three."""
    alone = train_fleet(data.subset([0]), recipe=QUICK, seed=2)
    fleet = train_fleet(data, recipe=QUICK, seed=2)
    for p, q in zip(alone.model.parameters(), fleet.model.parameters(), strict=True):
        torch.testing.assert_close(p[0], q[0], atol=1e-5, rtol=1e-4)


def test_early_stopping_ends_the_run():
    data = synthetic_fleet(n_units=2, n_rows=200, seed=1)
    recipe = TrainRecipe(name="es", lr=5e-2, batch_size=60, epochs=500, patience=2)
    fit = train_fleet(data, recipe=recipe, seed=0)
    assert len(fit.history) < 500


def test_fit_result_saves_and_loads(tmp_path, data, fit):
    path = fit.save(tmp_path / "fleet.safetensors")
    loaded = load_models(path)
    assert loaded.meta["unit_ids"] == data.unit_ids and loaded.meta["recipe"]["name"] == "quick"
    x = data.X_val[:, :20]
    with torch.no_grad():
        a = fit.out_scaler.inverse(fit.model(fit.in_scaler.transform(x)))
        b = loaded.out_scaler.inverse(loaded.model(loaded.in_scaler.transform(x)))
    assert torch.equal(a, b)


def test_unit_history_and_progress(data):
    fit = train_fleet(data.subset([0, 1]), recipe=QUICK.model_copy(update={"epochs": 1}),
                      progress=True)
    rows = fit.unit_history(1)
    assert rows[-1]["unit"] == 1 and isinstance(rows[-1]["val_force_rmse"], float)
    assert rows[-1]["val_force_rmse"] == fit.history[-1]["val_force_rmse"][1]


def test_default_recipes_are_valid():
    assert PAPER.schedule == "constant" and PAPER.lr == 1e-3
    assert FAST.schedule in ("onecycle", "cosine") and FAST.batch_size >= 256


def test_a_fleet_starts_from_a_trained_network(data, fit):
    """`init`: every unit begins at model 0 of a trained fleet, scalers included; a network of
    another shape is refused."""
    still = QUICK.model_copy(update={"lr": 1e-12, "epochs": 1, "keep_best": False})
    started = train_fleet(data, recipe=still, seed=9, init=fit)
    for p, q in zip(started.model.parameters(), fit.model.parameters(), strict=True):
        for u in range(3):
            torch.testing.assert_close(p[u], q[0], atol=1e-6, rtol=0)
    for mine, theirs in ((started.in_scaler, fit.in_scaler), (started.out_scaler, fit.out_scaler)):
        assert torch.equal(mine.mean[2], theirs.mean[0]) and torch.equal(mine.std[1], theirs.std[0])
    scratch = train_fleet(data, recipe=still, seed=9)
    assert started.history[0]["val_loss"][0] < scratch.history[0]["val_loss"][0] / 3
    with pytest.raises(ValueError, match="start network"):
        train_fleet(data, MLPConfig(sizes=(8, 16, 5)), recipe=still, init=fit)
