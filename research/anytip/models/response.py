"""A fleet's response model: each barometer's pressure given the contact, with a small code per
unit and barometer (the sensor's forward direction, contact -> pressures).

One network serves every barometer of every unit. Its input is the contact's labels (the
sensor model's targets, standardised over the training units), the barometer's own learnt
embedding and the code of that barometer in that unit. Unit-to-unit differences of the
fingertip (a barometer's placement, port tilt, direction defects, a void near its port, its
gain) belong to one barometer each, so a code per barometer holds them, and a new unit's codes
are few numbers (C x code_dim) that every press informs, wherever on the sensor it lands.

Where the targets hold a `force` vector the network is linear in it at a given place: it
outputs a sensitivity per force component and one for |F|, and the pressure is their sum
weighted by the force (p = F . K + |F| k0), which is what linear elasticity gives away from
saturation; its inputs still see |F|, so a knee or saturation can be learnt. Other targets
(an edge sensor's position and depth) give a plain output.

Shapes: U units, C barometers, D label columns, k = code_dim; pressures in Pa (tared).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass

import torch
from torch import Tensor, nn

from anytip.data.seeds import unit_seed


@dataclass(frozen=True)
class ResponseConfig:
    """The response network's size: per-barometer code, barometer embedding, hidden width and
    hidden layers (SiLU)."""

    code_dim: int = 16
    channel_dim: int = 8
    hidden: int = 128
    layers: int = 3

    def to_json(self) -> dict[str, int]:
        return asdict(self)


class ResponseModel(nn.Module):
    """Pressure (..., C) Pa of every barometer given labels (..., D) and codes (..., C, k).

    Buffers fix the scales, learnt from the training units' rows and saved with the weights:
    label_mean, label_std (D,); force_cols (F,) int64, the force columns (empty: no linear
    structure); force_scale () N, the RMS of |F|; pressure_scale () Pa, the RMS pressure.
    `codes` (U, C, k) are the training units' codes.
    """

    def __init__(self, n_units: int, n_channels: int, n_labels: int, force_cols: list[int],
                 config: ResponseConfig = ResponseConfig(), seed: int = 0):
        super().__init__()
        self.config, self.n_channels = config, n_channels
        g = torch.Generator().manual_seed(unit_seed(seed, 0, "response init"))
        self.register_buffer("label_mean", torch.zeros(n_labels))
        self.register_buffer("label_std", torch.ones(n_labels))
        self.register_buffer("force_cols", torch.tensor(force_cols, dtype=torch.int64))
        self.register_buffer("force_scale", torch.tensor(1.0))
        self.register_buffer("pressure_scale", torch.tensor(1.0))
        self.channel = nn.Parameter(0.5 * torch.randn(n_channels, config.channel_dim, generator=g))
        self.codes = nn.Parameter(torch.zeros(n_units, n_channels, config.code_dim))
        n_force = len(force_cols)
        d_in = len(self._context_cols(n_labels, force_cols)) + (1 if n_force else 0)
        d_in += config.channel_dim + config.code_dim
        sizes = [d_in] + [config.hidden] * config.layers + [n_force + 1 if n_force else 1]
        layers: list[nn.Module] = []
        for i, (a, b) in enumerate(zip(sizes[:-1], sizes[1:], strict=True)):
            layers.append(nn.Linear(a, b))
            if i < len(sizes) - 2:
                layers.append(nn.SiLU())
        self.net = nn.Sequential(*layers)
        with torch.no_grad():
            for m in self.net:
                if isinstance(m, nn.Linear):
                    nn.init.kaiming_uniform_(m.weight, a=5**0.5, generator=g)
                    nn.init.uniform_(m.bias, -1 / m.in_features**0.5, 1 / m.in_features**0.5, generator=g)

    @staticmethod
    def _context_cols(n_labels: int, force_cols: list[int]) -> list[int]:
        """The label columns the network reads as they are: every one but the force's."""
        return [j for j in range(n_labels) if j not in set(force_cols)]

    @property
    def n_units(self) -> int:
        return int(self.codes.shape[0])

    def set_scales(self, labels: Tensor, pressures: Tensor) -> None:
        """Scales from the training units' rows: labels (n, D), pressures (n, C) Pa."""
        with torch.no_grad():
            self.label_mean.copy_(labels.mean(0))
            self.label_std.copy_(labels.std(0).clamp_min(1e-12))
            if len(self.force_cols):
                force = labels[:, self.force_cols]
                self.force_scale.copy_(force.norm(dim=1).pow(2).mean().sqrt().clamp_min(1e-12))
            self.pressure_scale.copy_(pressures.pow(2).mean().sqrt().clamp_min(1e-12))

    def forward(self, labels: Tensor, codes: Tensor) -> Tensor:
        """labels (*, D) physical; codes broadcastable to (*, C, k) -> pressures (*, C) Pa."""
        return self._pressure(labels.unsqueeze(-2), codes)

    def _pressure(self, labels: Tensor, codes: Tensor) -> Tensor:
        """labels (*, 1, D) shared by every barometer, or (*, C, D) one copy per barometer; codes
        broadcastable to (*, C, k) -> pressures (*, C) Pa."""
        cols = self._context_cols(labels.shape[-1], self.force_cols.tolist())
        context = (labels[..., cols] - self.label_mean[cols]) / self.label_std[cols]
        if len(self.force_cols):
            force = labels[..., self.force_cols] / self.force_scale
            magnitude = force.norm(dim=-1, keepdim=True)
            context = torch.cat([context, magnitude], -1)
        lead = torch.broadcast_shapes(labels.shape[:-2], codes.shape[:-2])
        C = self.n_channels
        inp = torch.cat([context.expand(*lead, C, context.shape[-1]),
                         self.channel.expand(*lead, C, self.channel.shape[-1]),
                         codes.expand(*lead, C, codes.shape[-1])], -1)
        out = self.net(inp)
        if len(self.force_cols):
            n_force = len(self.force_cols)
            pressure = (out[..., :n_force] * force).sum(-1) + out[..., n_force] * magnitude[..., 0]
        else:
            pressure = out[..., 0]
        return pressure * self.pressure_scale

    def jacobians(self, labels: Tensor, codes: Tensor) -> tuple[Tensor, Tensor, Tensor]:
        """labels (*, D) physical; codes broadcastable to (*, C, k) -> the pressures (*, C) Pa, their
        derivative in each row's own labels (*, C, D) Pa per label unit and in each barometer's own
        code (*, C, k), detached. Pressure c of a row depends on that row's labels and code c alone,
        so one backward pass through per-(row, barometer) copies of both gives every derivative:
        about the cost of two forward passes, where forward tangents cost one per label column."""
        pressure, derivatives = self.linearisation(labels, codes)
        return (pressure, *derivatives())

    def linearisation(self, labels: Tensor, codes: Tensor
                      ) -> tuple[Tensor, Callable[[], tuple[Tensor, Tensor]]]:
        """`jacobians` in two parts: the pressures (*, C) Pa now, and a call that gives their
        derivatives ((*, C, D), (*, C, k)) from the same forward pass, once, when asked. A caller that
        may not need them (a refused trial step) skips the backward pass, about two thirds of the cost."""
        C, k = self.n_channels, codes.shape[-1]
        lead = torch.broadcast_shapes(labels.shape[:-1], codes.shape[:-2])
        y = labels.unsqueeze(-2).expand(*lead, C, labels.shape[-1]).detach().clone().requires_grad_(True)
        z = codes.detach().expand(*lead, C, k).clone().requires_grad_(True)
        with torch.enable_grad():
            pressure = self._pressure(y, z)

        def derivatives() -> tuple[Tensor, Tensor]:
            dy, dz = torch.autograd.grad(pressure.sum(), (y, z))
            return dy, dz

        return pressure.detach(), derivatives

    def code_parameters(self) -> list[nn.Parameter]:
        return [self.codes]

    def shared_parameters(self) -> list[nn.Parameter]:
        return [self.channel, *self.net.parameters()]
