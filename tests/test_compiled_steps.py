"""The compiled training steps of one ReLU network (train/compiled_steps.py) against torch's: the written-out
gradients (`BatchedMLP.mse_grads`) and the fused Adam kernel, step by step."""

import pytest
import torch

from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.train.compiled_steps import CompiledSteps, compile_now, compiled_serves
from anytip.train.data import FleetBatchData, UnitTensors
from anytip.train.fleet import train_fleet
from anytip.train.recipe import FAST, make_optimizer, set_lr
from test_models_mlp import _autograd_activations, _grad_rounding_bound

BATCH, STEPS = 32, 12


def _rows(seed: int) -> tuple[torch.Tensor, torch.Tensor]:
    g = torch.Generator().manual_seed(seed)
    return torch.randn(STEPS, 1, BATCH, 8, generator=g), torch.randn(STEPS, 1, BATCH, 5, generator=g)


@pytest.mark.parametrize(("optimizer", "decay"), [("adam", 0.0), ("adam", 0.01), ("adamw", 0.05)])
def test_compiled_steps_equal_torch_within_float32_rounding(optimizer, decay):
    """Twelve steps in three stretches of varying learning rate: every weight within a few float32
    units of the torch step's, and the losses' sum equal to float32 rounding."""
    recipe = FAST.model_copy(update={"optimizer": optimizer, "weight_decay": decay, "batch_size": BATCH})
    X, Y = _rows(0)
    lrs = [1e-3 * (1 + k) for k in range(STEPS)]
    torch_net, compiled_net = BatchedMLP(1, MLPConfig(), seed=3), BatchedMLP(1, MLPConfig(), seed=3)
    opt, loss = make_optimizer(torch_net.parameters(), recipe), torch.zeros(1)
    for k in range(STEPS):
        set_lr(opt, lrs[k])
        loss += torch_net.mse_grads(X[k], Y[k])
        opt.step()
    steps = CompiledSteps(compiled_net, recipe)
    got = sum(steps.run(X[a:b], Y[a:b], lrs[a:b]) for a, b in ((0, 1), (1, 7), (7, STEPS)))
    for p, q in zip(torch_net.parameters(), compiled_net.parameters(), strict=True):
        torch.testing.assert_close(q, p, atol=1e-6, rtol=1e-5)
    torch.testing.assert_close(got, loss, atol=0, rtol=1e-5)
    assert steps.t == STEPS


@pytest.mark.parametrize("sizes", [(8, 12, 64, 64, 5), (6, 3), (8, 40, 20), (8, 4, 5)])
def test_a_compiled_steps_gradients_lie_within_float32_rounding_of_the_exact_ones(sizes):
    """One step at learning rate 0 (the weights stay): its loss and the gradients it leaves in its buffers
    lie within the rounding bound of the exact ones through the float32 activations it computed, which
    lie within float32 rounding of autograd's."""
    model = BatchedMLP(1, MLPConfig(sizes=sizes), seed=2)
    g = torch.Generator().manual_seed(0)
    x, y = torch.randn(1, 1, 512, sizes[0], generator=g), torch.randn(1, 1, 512, sizes[-1], generator=g)
    x[..., :8, :] = 0.0
    steps = CompiledSteps(model, FAST.model_copy(update={"batch_size": 512}))
    loss = steps.run(x, y, [0.0])
    hidden = [torch.from_numpy(h.copy())[None] for h in steps.h[:-1]]
    for ours, theirs in zip(hidden, _autograd_activations(model, x[0]), strict=True):
        assert float((ours - theirs).abs().max()) <= 1e-5 * float(theirs.abs().max())
    loss_bound, bounds, exact_loss, exact = _grad_rounding_bound(model, x[0], y[0], hidden)
    assert bool(((loss.double() - exact_loss).abs() <= loss_bound).all())
    grads = [*(torch.from_numpy(w)[None] for w in steps.gW),
             *(torch.from_numpy(b)[None, None] for b in steps.gb)]
    for got, want, bound in zip(grads, exact, bounds, strict=True):
        assert got.shape == want.shape and bool(((got.double() - want).abs() <= bound).all())
        assert float(bound.max()) < 1e-2 * float(want.abs().max())  # a slip moves a gradient by its size


def test_a_stretch_moves_the_weights_in_the_networks_own_memory():
    """The compiled steps write the network's weights themselves: what the trainer evaluates, keeps and
    saves is what they trained."""
    net = BatchedMLP(1, MLPConfig(), seed=1)
    before = [p.detach().clone() for p in net.parameters()]
    X, Y = _rows(1)
    CompiledSteps(net, FAST.model_copy(update={"batch_size": BATCH})).run(X[:3], Y[:3], [1e-2] * 3)
    assert all(not torch.equal(p, q) for p, q in zip(net.parameters(), before, strict=True))


def test_a_batch_of_another_size_is_refused():
    X, Y = _rows(2)
    recipe = FAST.model_copy(update={"batch_size": BATCH + 1})
    steps = CompiledSteps(BatchedMLP(1, MLPConfig(), seed=0), recipe)
    with pytest.raises(ValueError, match=f"batches of {BATCH} rows"):
        steps.run(X[:1], Y[:1], [1e-3])


def test_compile_now_compiles_the_deployed_shapes_steps():
    compile_now()  # what `make venv` runs; loads from numba's cache when compiled before


def test_only_one_relu_network_on_a_cpu_steps_compiled():
    cpu = torch.device("cpu")
    assert compiled_serves(BatchedMLP(1, MLPConfig(), seed=0), cpu)
    assert not compiled_serves(BatchedMLP(2, MLPConfig(), seed=0), cpu)
    assert not compiled_serves(BatchedMLP(1, MLPConfig(activation="tanh"), seed=0), cpu)
    assert not compiled_serves(BatchedMLP(1, MLPConfig(), seed=0).double(), cpu)


def test_train_fleet_steps_one_network_compiled_as_torch_would(monkeypatch):
    """A network trained alone by `train_fleet` (compiled) ends where torch's steps take it (the compiled
    path turned off), within what float32 rounding grows to over a short training."""
    g = torch.Generator().manual_seed(5)
    X, Y = torch.randn(300, 8, generator=g) * 1e3, torch.randn(300, 5, generator=g)
    data = FleetBatchData.from_units([UnitTensors(X[:240], Y[:240], X[240:], Y[240:], "U0")])
    recipe = FAST.model_copy(update={"epochs": 3, "batch_size": 64})
    compiled = train_fleet(data, recipe=recipe, seed=0)
    monkeypatch.setattr("anytip.train.fleet.compiled_serves", lambda model, device: False)
    plain = train_fleet(data, recipe=recipe, seed=0)
    for p, q in zip(plain.model.parameters(), compiled.model.parameters(), strict=True):
        torch.testing.assert_close(q, p, atol=1e-5, rtol=1e-4)
    assert [r["step"] for r in compiled.history] == [r["step"] for r in plain.history]
