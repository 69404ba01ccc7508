"""A fleet of small MLPs held as one batched model.

Layer l of model u computes h @ weights[l][u] + biases[l][u], so a forward pass over
every model is one `torch.baddbmm` per layer: x (U, B, in) -> (U, B, out).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, Literal

import torch
import torch.nn.functional as F
from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator
from torch import Tensor, nn

from anytip.data.seeds import unit_seed
from anytip.errors import AnytipError

# leaky_relu (negative slope 0.01, torch's default) and hardswish (x * clamp(x + 3, 0, 6) / 6) need
# only compares, adds and multiplies, so they export without libm; tanh, gelu and silu do not.
Activation = Literal["relu", "tanh", "gelu", "silu", "leaky_relu", "hardswish"]
ACTIVATIONS = {"relu": torch.relu, "tanh": torch.tanh, "gelu": F.gelu, "silu": F.silu,
               "leaky_relu": F.leaky_relu, "hardswish": F.hardswish}
ACTIVATION_MODULES = {"relu": nn.ReLU, "tanh": nn.Tanh, "gelu": nn.GELU, "silu": nn.SiLU,
                      "leaky_relu": nn.LeakyReLU, "hardswish": nn.Hardswish}

MAX_WIDTH, MAX_LAYERS = 4096, 32  # far beyond a microcontroller; bounds a typo's memory
Plain = list[tuple[Tensor, Tensor]]  # one model as [(W (in, out), b (out,)), ...]
# A batched product with fewer output columns than this is taken as (b^T a^T)^T: MKL's path for a
# narrow product (the 64-to-5 output layer at 512 rows) is 4-6 times slower than the transposed one.
# At 12 columns the two take about as long, and the transposed result's strides slow the ReLU
# backward that follows it, so 8 it is (measured on one Zen 4 core; with train/fused_adam.py a
# one-unit step at batch 512 went from about 0.7 to 0.45 ms, a 64-unit step at 256 by about a quarter).
NARROW_OUT = 8


def _bmm(a: Tensor, b: Tensor, bias: Tensor | None = None) -> Tensor:
    """a (U, M, K) @ b (U, K, N) [+ bias (U, 1, N)], transposed where N < NARROW_OUT (a strided view
    then)."""
    if b.shape[2] < NARROW_OUT:
        at, bt = a.transpose(1, 2), b.transpose(1, 2)
        out = torch.bmm(bt, at) if bias is None else torch.baddbmm(bias.transpose(1, 2), bt, at)
        return out.transpose(1, 2)
    return torch.bmm(a, b) if bias is None else torch.baddbmm(bias, a, b)


class MLPConfig(BaseModel):
    """Shape of one MLP: layer widths from input to output and the nonlinearities.

    A spec names either `hidden` (the hidden widths; input and output widths then come
    from the sensor model, see `for_sensor`) or `sizes` (every width, checked against the
    sensor model). Without either, `sizes` is the fingertip's 8-12-64-64-5.
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    sizes: tuple[int, ...] = Field((8, 12, 64, 64, 5), min_length=2, max_length=MAX_LAYERS + 1)
    hidden: tuple[int, ...] | None = Field(None, max_length=MAX_LAYERS - 1)
    activation: Activation = "relu"
    output_activation: Activation | None = None

    @field_validator("sizes")
    @classmethod
    def _check_sizes(cls, sizes: tuple[int, ...]) -> tuple[int, ...]:
        if len(sizes) < 2 or min(sizes) < 1 or max(sizes) > MAX_WIDTH:
            raise ValueError(f"sizes {sizes} needs at least an input and an output width, "
                             f"all in 1..{MAX_WIDTH}")
        return sizes

    @model_validator(mode="before")
    @classmethod
    def _hidden_to_sizes(cls, data: Any) -> Any:
        """`hidden` alone sets `sizes` to (8, *hidden, 5) until `for_sensor` sets the ends;
        `sizes` given as well names every width and wins."""
        if not isinstance(data, dict):
            return data
        if data.get("hidden") is None:  # strict validation takes a tuple only as a tuple here
            return {**data, "sizes": tuple(data["sizes"])} if isinstance(data.get("sizes"), list) else data
        hidden = tuple(data["hidden"])
        if any(not isinstance(h, int) or isinstance(h, bool) or not 1 <= h <= MAX_WIDTH for h in hidden):
            raise ValueError(f"hidden {list(hidden)}: widths must be integers in 1..{MAX_WIDTH}")
        if "sizes" in data:  # every width named (e.g. over a block's hidden): sizes wins
            return {**data, "sizes": tuple(data["sizes"]), "hidden": None}
        return {**data, "sizes": (8, *hidden, 5), "hidden": hidden}

    def for_sensor(self, channels: int, outputs: int, source: str, sensor_model: str) -> MLPConfig:
        """This shape with input width `channels` and output width `outputs` (the sensor model's
        pressure channels and label columns). Explicit `sizes` must already agree: AnytipError
        naming `source`'s key otherwise. The default shape keeps its hidden widths."""
        if self.hidden is None and "sizes" in self.model_fields_set:
            if self.sizes[0] != channels:
                raise AnytipError(f"{source}: key 'model.sizes' {list(self.sizes)}: the input width "
                                  f"{self.sizes[0]} must equal the {channels} pressure channels of sensor "
                                  f"model {sensor_model!r} (or name only the hidden widths: 'model.hidden')")
            if self.sizes[-1] != outputs:
                raise AnytipError(f"{source}: key 'model.sizes' {list(self.sizes)}: the output width "
                                  f"{self.sizes[-1]} must equal the {outputs} label columns of sensor "
                                  f"model {sensor_model!r} (or name only the hidden widths: 'model.hidden')")
            return self
        return self.model_copy(update={"sizes": (channels, *self.sizes[1:-1], outputs)})

    @property
    def n_params(self) -> int:
        """Weights and biases of one model."""
        return sum((i + 1) * o for i, o in zip(self.sizes[:-1], self.sizes[1:], strict=True))


class BatchedMLP(nn.Module):
    """U independent MLPs of one shape: weights[l] (U, in, out), biases[l] (U, 1, out).

    `seed` is either one int (model u is initialised from `unit_seed(seed, u)`) or one seed
    per model. Initialisation matches nn.Linear's default: W, b ~ U(-1/sqrt(in), 1/sqrt(in)).
    """

    def __init__(self, n_models: int, config: MLPConfig, seed: int | Sequence[int] = 0):
        super().__init__()
        self.n_models, self.config = n_models, config
        pairs = list(zip(config.sizes[:-1], config.sizes[1:], strict=True))
        self.weights = nn.ParameterList(nn.Parameter(torch.empty(n_models, i, o)) for i, o in pairs)
        self.biases = nn.ParameterList(nn.Parameter(torch.empty(n_models, 1, o)) for _, o in pairs)
        seeds = [unit_seed(seed, u) for u in range(n_models)] if isinstance(seed, int) else seed
        self.reset_parameters(seeds)

    @torch.no_grad()
    def reset_parameters(self, seeds: Sequence[int]) -> None:
        """Initialise model u from its own CPU generator, so its weights depend on seeds[u] only."""
        if len(seeds) != self.n_models:
            raise ValueError(f"got {len(seeds)} seeds for {self.n_models} models")
        for u, s in enumerate(seeds):
            g = torch.Generator().manual_seed(int(s))
            for W, b in zip(self.weights, self.biases, strict=True):
                fan_in, fan_out = W.shape[1], W.shape[2]
                bound = 1.0 / math.sqrt(fan_in)
                # drawn as (out, in) like nn.Linear.weight, then stored transposed
                w = torch.empty(fan_out, fan_in).uniform_(-bound, bound, generator=g)
                W[u].copy_(w.T)
                b[u, 0].copy_(torch.empty(fan_out).uniform_(-bound, bound, generator=g))

    def forward(self, x: Tensor) -> Tensor:
        """x (U, B, in) -> (U, B, out), in whatever units the model was trained on."""
        act = ACTIVATIONS[self.config.activation]
        last = len(self.weights) - 1
        for k, (W, b) in enumerate(zip(self.weights, self.biases, strict=True)):
            x = torch.baddbmm(b, x, W)
            if k < last:
                x = act(x)
        if self.config.output_activation is not None:
            x = ACTIVATIONS[self.config.output_activation](x)
        return x

    def mse_grads(self, x: Tensor, y: Tensor) -> Tensor:
        """Each model's mean squared error on x (U, B, in), y (U, B, out): (U,), detached, with the
        gradients of its sum left in the weights' `.grad` (replacing what was there), as
        `loss.sum().backward()` after `zero_grad` leaves them.

        ReLU networks without an output activation (the deployed kind) get the chain rule written
        out, without autograd's per-operation bookkeeping, which is most of a tiny network's step on
        a CPU core. The hidden layers' forward products are autograd's own, so every ReLU sees the
        same values; the output layer's product and the gradients' products with fewer than
        NARROW_OUT output columns are taken transposed (`_bmm`), so the gradients equal autograd's
        within float32 rounding rather than bit for bit (tests/test_models_mlp.py bounds the
        difference). Any other activation goes through autograd."""
        if self.config.activation != "relu" or self.config.output_activation is not None:
            for p in self.parameters():
                p.grad = None
            loss = ((self(x) - y) ** 2).mean(dim=(1, 2))
            loss.sum().backward()
            return loss.detach()
        with torch.no_grad():
            # the ParameterLists' own dicts: iterating a ParameterList costs 10-20 us of a 0.5 ms step
            weights, biases = self.weights._parameters.values(), self.biases._parameters.values()
            layers = list(zip(weights, biases, strict=True))
            inputs, h = [], x
            for k, (W, b) in enumerate(layers):
                inputs.append(h)
                if k < len(layers) - 1:  # autograd's product, so every ReLU sees autograd's values
                    h = torch.baddbmm(b, h, W).relu_()  # in place: ReLU's backward reads its result alone
                else:
                    h = _bmm(h, W, b)
            err = h - y
            loss = (err**2).mean(dim=(1, 2))
            g = err * (2 / (err.shape[1] * err.shape[2]))  # d loss_u / d output, rounded as autograd's
            for k in range(len(layers) - 1, -1, -1):
                (W, b), a = layers[k], inputs[k]
                W.grad = _bmm(a.transpose(1, 2), g).contiguous()  # the weight's layout, as autograd's
                b.grad = g.sum(1, keepdim=True)
                if k > 0:  # back through W and the ReLU that made a (autograd's own ReLU backward)
                    g = torch.ops.aten.threshold_backward(_bmm(g, W.transpose(1, 2)), a, 0)
        return loss

    def is_one_relu_network(self) -> bool:
        """Whether this is one ReLU network without an output activation (the deployed kind, alone)."""
        config = self.config
        return self.n_models == 1 and config.activation == "relu" and config.output_activation is None

    def to_plain(self, i: int) -> Plain:
        """Model i as [(W (in, out), b (out,)), ...], detached copies on the model's device."""
        return [(W[i].detach().clone(), b[i, 0].detach().clone())
                for W, b in zip(self.weights, self.biases, strict=True)]

    def model_slice(self, i: int) -> BatchedMLP:
        """A one-model BatchedMLP holding a copy of model i."""
        return BatchedMLP.from_plain([self.to_plain(i)], self.config)

    def to_sequential(self, i: int) -> nn.Sequential:
        """Model i as a plain nn.Sequential of nn.Linear layers (weights copied)."""
        return plain_to_sequential(self.to_plain(i), self.config)

    @classmethod
    def from_plain(cls, models: Sequence[Plain], config: MLPConfig) -> BatchedMLP:
        """Stack per-model [(W (in, out), b (out,)), ...] lists into one BatchedMLP (of their dtype)."""
        out = cls(len(models), config, seed=[0] * len(models))
        out.to(device=models[0][0][0].device, dtype=models[0][0][0].dtype)
        with torch.no_grad():
            for k, (W, b) in enumerate(zip(out.weights, out.biases, strict=True)):
                W.copy_(torch.stack([m[k][0] for m in models]))
                b.copy_(torch.stack([m[k][1] for m in models]).unsqueeze(1))
        return out


def plain_to_sequential(plain: Plain, config: MLPConfig) -> nn.Sequential:
    """[(W (in, out), b (out,)), ...] -> nn.Sequential(Linear, act, ..., Linear[, out act])."""
    layers: list[nn.Module] = []
    for k, (W, b) in enumerate(plain):
        lin = nn.Linear(W.shape[0], W.shape[1], device=W.device)
        with torch.no_grad():
            lin.weight.copy_(W.T)
            lin.bias.copy_(b)
        layers.append(lin)
        if k < len(plain) - 1:
            layers.append(ACTIVATION_MODULES[config.activation]())
    if config.output_activation is not None:
        layers.append(ACTIVATION_MODULES[config.output_activation]())
    return nn.Sequential(*layers)


def sequential_to_plain(net: nn.Sequential) -> Plain:
    """The nn.Linear layers of `net` as [(W (in, out), b (out,)), ...] (detached copies)."""
    return [(m.weight.detach().T.clone(), m.bias.detach().clone())
            for m in net if isinstance(m, nn.Linear)]
