import json

import pytest
import torch
from safetensors.torch import load_file, save_file
from torch import nn

import anytip.models.scaler as scaler_module
from anytip.deploy.rounding import U_FLOAT32, gamma
from anytip.errors import AnytipError
from anytip.models import (
    BatchedMLP,
    MLPConfig,
    ModelFileError,
    Scaler,
    load_models,
    plain_to_sequential,
    save_models,
)

CONFIG = MLPConfig()


def test_config_rejects_unknown_keys_and_bad_values():
    with pytest.raises(ValueError):
        MLPConfig(sizes=(8, 5), width=3)
    with pytest.raises(ValueError):
        MLPConfig(activation="sigmoid")
    with pytest.raises(ValueError):
        MLPConfig(sizes=(8,))
    assert CONFIG.n_params == 9 * 12 + 13 * 64 + 65 * 64 + 65 * 5


@pytest.mark.parametrize("activation", ["relu", "tanh", "gelu", "silu"])
def test_batched_forward_equals_per_unit_sequential(activation):
    config = MLPConfig(activation=activation, output_activation="tanh")
    model = BatchedMLP(3, config, seed=1)
    x = torch.randn(3, 50, 8)
    out = model(x)
    assert out.shape == (3, 50, 5)
    for u in range(3):
        net = model.to_sequential(u)
        assert isinstance(net[0], nn.Linear)
        torch.testing.assert_close(out[u], net(x[u]), atol=1e-6, rtol=0)
        plain = model.to_plain(u)
        assert [tuple(W.shape) for W, _ in plain] == [(8, 12), (12, 64), (64, 64), (64, 5)]
        torch.testing.assert_close(plain_to_sequential(plain, config)(x[u]), net(x[u]))
        torch.testing.assert_close(model.model_slice(u)(x[u : u + 1])[0], out[u], atol=1e-6, rtol=0)


def _autograd_grads(model, x, y):
    model.zero_grad(set_to_none=True)
    loss = ((model(x) - y) ** 2).mean(dim=(1, 2))
    loss.sum().backward()
    return loss.detach(), [p.grad.clone() for p in model.parameters()]


def _autograd_activations(model, x):
    """The float32 hidden activations (after each ReLU) as autograd's forward computes them."""
    acts, h = [], x
    with torch.no_grad():
        for k in range(len(model.weights) - 1):
            h = torch.relu(torch.baddbmm(model.biases[k], h, model.weights[k]))
            acts.append(h)
    return acts


def _grad_rounding_bound(model, x, y, hidden=None):
    """Bounds (float64) on |float32 gradient - exact gradient| of each weight of a ReLU `model`,
    for any summation order of every product and sum, given the float32 hidden activations `hidden`
    the computation used (default: autograd's) (Higham's |fl(A B) - A B| <= gamma_K |A| |B|, carried
    through the chain rule on magnitudes), and on the loss; and the exact loss and gradients through
    those activations."""
    u = U_FLOAT32
    W = [w.detach().double() for w in model.weights]
    b = [v.detach().double() for v in model.biases]
    hidden = _autograd_activations(model, x) if hidden is None else hidden
    acts = [x.double(), *(h.double() for h in hidden)]
    a = acts[-1]
    e_h = gamma(W[-1].shape[1] + 1, u) * (a.abs() @ W[-1].abs() + b[-1].abs())
    err = a @ W[-1] + b[-1] - y.double()
    e_err = e_h + u * (err.abs() + e_h)
    c = 2 / (err.shape[1] * err.shape[2])
    g, e_g = c * err, c * e_err + u * c * (err.abs() + e_err)
    loss_bound = (2 * err.abs() * e_err + e_err**2 + u * (err.abs() + e_err) ** 2).mean(dim=(1, 2))
    n_out = err.shape[1] * err.shape[2]
    loss_bound = loss_bound + gamma(n_out + 1, u) * ((err.abs() + e_err) ** 2).mean(dim=(1, 2))
    bounds, exact = [None] * (2 * len(W)), [None] * (2 * len(W))
    B = x.shape[1]
    for k in range(len(W) - 1, -1, -1):
        a, mag = acts[k], g.abs() + e_g
        bounds[k] = a.abs().transpose(1, 2) @ e_g + gamma(B, u) * (a.abs().transpose(1, 2) @ mag)
        bounds[len(W) + k] = e_g.sum(1, keepdim=True) + gamma(B, u) * mag.sum(1, keepdim=True)
        exact[k], exact[len(W) + k] = a.transpose(1, 2) @ g, g.sum(1, keepdim=True)
        if k > 0:
            mask = (a > 0).double()
            W_abs = W[k].abs().transpose(1, 2)
            e_g = e_g @ W_abs + gamma(W[k].shape[2], u) * (mag @ W_abs)
            g, e_g = (g @ W[k].transpose(1, 2)) * mask, e_g * mask
    # bounds and exact gradients in parameters() order: weights, then biases
    return loss_bound, bounds, (err**2).mean(dim=(1, 2)), exact


@pytest.mark.parametrize("sizes", [(8, 12, 64, 64, 5), (6, 3), (8, 40, 20), (8, 4, 5)])
def test_mse_grads_equal_autograd_within_float32_rounding(sizes):
    """ReLU networks: the written-out chain rule (narrow products transposed) and autograd each lie
    within the rounding bound of the exact gradient, so they differ by at most twice it."""
    model = BatchedMLP(3, MLPConfig(sizes=sizes), seed=2)
    g = torch.Generator().manual_seed(0)
    x, y = torch.randn(3, 512, sizes[0], generator=g), torch.randn(3, 512, sizes[-1], generator=g)
    x[:, :8] = 0.0
    loss, grads = _autograd_grads(model, x, y)
    for p in model.parameters():
        p.grad = torch.full_like(p, 7.0)  # replaced, not added to
    got = model.mse_grads(x, y)
    loss_bound, bounds, _, _ = _grad_rounding_bound(model, x, y)
    assert not got.requires_grad and bool(((got - loss).double().abs() <= 2 * loss_bound).all())
    for p, want, bound in zip(model.parameters(), grads, bounds, strict=True):
        # the weight's own layout (a fused optimizer kernel walks weight and gradient as flat memory)
        assert p.grad.shape == want.shape and p.grad.stride() == p.stride()
        assert bool(((p.grad - want).double().abs() <= 2 * bound).all())
        # a slip (a wrong or missing product) moves a gradient by its own size; the bound is 0.01-0.2% of it
        assert float(bound.max()) < 1e-2 * float(want.abs().max())


@pytest.mark.parametrize(("sizes", "activation", "output"), [((8, 16, 5), "tanh", None),
                                                             ((8, 16, 5), "relu", "tanh")])
def test_mse_grads_equal_autograd_bit_for_bit_off_relu(sizes, activation, output):
    """Other activations go through autograd itself."""
    model = BatchedMLP(3, MLPConfig(sizes=sizes, activation=activation, output_activation=output), seed=2)
    g = torch.Generator().manual_seed(0)
    x, y = torch.randn(3, 64, sizes[0], generator=g), torch.randn(3, 64, sizes[-1], generator=g)
    loss, grads = _autograd_grads(model, x, y)
    for p in model.parameters():
        p.grad = torch.full_like(p, 7.0)
    got = model.mse_grads(x, y)
    assert torch.equal(got, loss) and not got.requires_grad
    for p, want in zip(model.parameters(), grads, strict=True):
        assert torch.equal(p.grad, want)


def test_init_is_per_unit_seeded_and_default_like():
    a, b = BatchedMLP(3, CONFIG, seed=7), BatchedMLP(5, CONFIG, seed=7)
    for Wa, Wb in zip(a.weights, b.weights, strict=True):
        assert torch.equal(Wa, Wb[:3])  # unit u's init does not depend on the fleet size
        assert Wa.abs().max() <= 1 / Wa.shape[1] ** 0.5
    assert not torch.equal(a.weights[0][0], a.weights[0][1])
    assert not torch.equal(a.weights[0], BatchedMLP(3, CONFIG, seed=8).weights[0])


def test_from_plain_round_trip():
    model = BatchedMLP(4, CONFIG, seed=3)
    back = BatchedMLP.from_plain([model.to_plain(u) for u in range(4)], CONFIG)
    for p, q in zip(model.parameters(), back.parameters(), strict=True):
        assert torch.equal(p, q)


def test_scaler_fits_only_the_given_rows_and_floors_std():
    g = torch.Generator().manual_seed(0)
    x = torch.randn(2, 100, 3, generator=g) * torch.tensor([1e4, 5.0, 0.0]) + 7.0
    n = torch.tensor([100, 40])
    x[1, 40:] = 1e9  # padding beyond n must not count
    s = Scaler.fit(x, n)
    torch.testing.assert_close(s.mean[1, 0], x[1, :40].double().mean(0).float())
    torch.testing.assert_close(s.std[0, 0, :2], x[0, :, :2].double().std(0, correction=0).float())
    # the constant channel gets the floor: 1e-6 of the unit's largest std
    torch.testing.assert_close(s.std[:, 0, 2], 1e-6 * s.std[:, 0, 0])
    z = s.transform(x)
    # float32 round trip of values ~1e4: a few ulps
    torch.testing.assert_close(s.inverse(z)[:, :40], x[:, :40], rtol=1e-5, atol=1e-3)
    assert s.slice(1).mean.shape == (1, 1, 3)


def test_scaler_reads_its_rows_a_block_at_a_time_and_pools_units_without_stacking(monkeypatch):
    """Statistics summed a block of rows at a time equal those of one float64 pass to float32
    rounding; the pooled scaler equals `fit` on the units' real rows stacked into one; padding,
    even NaN, is never read."""
    g = torch.Generator().manual_seed(1)
    x = torch.randn(3, 500, 4, generator=g) * torch.tensor([2e4, 3.0, 1.0, 50.0]) + 1e5
    n = torch.tensor([500, 37, 260])
    for u in range(3):
        x[u, int(n[u]):] = float("nan")
    monkeypatch.setattr(scaler_module, "ELEMENTS_PER_PASS", 3 * 4 * 7)  # 7 rows a block
    s = Scaler.fit(x, n)
    for u in range(3):
        rows = x[u, : int(n[u])].double()
        torch.testing.assert_close(s.mean[u, 0], rows.mean(0).float(), rtol=2e-7, atol=0)
        torch.testing.assert_close(s.std[u, 0], rows.std(0, correction=0).float(), rtol=2e-7, atol=0)
    pooled = Scaler.pooled(x, n)
    stacked = Scaler.fit(torch.cat([x[u, : int(n[u])] for u in range(3)])[None])
    assert pooled.mean.shape == (1, 1, 4)
    torch.testing.assert_close(pooled.mean, stacked.mean, rtol=2e-7, atol=0)
    torch.testing.assert_close(pooled.std, stacked.std, rtol=2e-7, atol=0)
    with pytest.raises(ValueError, match="at least one row"):
        Scaler.pooled(x, torch.tensor([5, 0, 5]))


def _scalers(U):
    return (Scaler(torch.randn(U, 1, 8) * 1e3, torch.rand(U, 1, 8) * 1e4 + 1),
            Scaler(torch.randn(U, 1, 5), torch.rand(U, 1, 5) + 0.1))


def test_save_load_round_trip_is_exact(tmp_path):
    model = BatchedMLP(3, CONFIG, seed=2)
    ins, outs = _scalers(3)
    meta = {"unit_ids": ["a", "b", "c"], "output_names": ["fx", "fy", "fz", "theta", "phi"]}
    path = save_models(tmp_path / "fleet.safetensors", model, ins, outs, meta)
    assert path.exists() and path.with_suffix(".json").exists()
    header = json.loads(path.with_suffix(".json").read_text())
    assert header["config"]["sizes"] == [8, 12, 64, 64, 5]
    loaded = load_models(path)
    for p, q in zip(model.parameters(), loaded.model.parameters(), strict=True):
        assert torch.equal(p, q)
    assert torch.equal(loaded.in_scaler.std, ins.std) and torch.equal(loaded.out_scaler.mean, outs.mean)
    assert loaded.meta == meta and loaded.model.config == CONFIG
    save_models(tmp_path / "dir", model, ins, outs)  # a directory gets model.safetensors
    assert load_models(tmp_path / "dir").model.n_models == 3


def test_load_with_wrong_shape_names_the_file(tmp_path):
    model = BatchedMLP(2, CONFIG, seed=0)
    path = save_models(tmp_path / "m.safetensors", model, *_scalers(2))
    tensors = load_file(str(path))
    tensors["weights.1"] = torch.zeros(2, 12, 32)
    save_file(tensors, str(path))
    with pytest.raises(ModelFileError, match=r"m\.safetensors.*weights\.1.*\(2, 12, 32\)"):
        load_models(path)
    del tensors["weights.1"]
    save_file(tensors, str(path))
    with pytest.raises(ModelFileError, match=r"m\.safetensors.*missing \['weights\.1'\]"):
        load_models(path)


def test_load_refuses_bad_metadata(tmp_path):
    path = save_models(tmp_path / "m.safetensors", BatchedMLP(2, CONFIG), *_scalers(2))
    meta = path.with_suffix(".json")
    header = json.loads(meta.read_text())
    meta.write_text(json.dumps(header | {"format_version": 99}))
    with pytest.raises(AnytipError, match=r"m\.json.*format_version 99"):
        load_models(path)
    with pytest.raises(ModelFileError, match="not found"):
        load_models(tmp_path / "nothing.safetensors")
    with pytest.raises(ValueError, match="unit_ids"):
        save_models(tmp_path / "x", BatchedMLP(2, CONFIG), *_scalers(2), meta={"unit_ids": ["a"]})
