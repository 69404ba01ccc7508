"""Per-model affine standardisation of inputs or outputs: z = (x - mean) / std."""

from __future__ import annotations

from dataclasses import dataclass

import torch
from torch import Tensor


@dataclass
class Scaler:
    """mean, std (U, 1, d) in the data's physical units (Pa for pressures, N and rad for outputs)."""

    mean: Tensor
    std: Tensor

    @classmethod
    def fit(cls, x: Tensor, n: Tensor | None = None, rel_floor: float = 1e-6) -> Scaler:
        """Fit on x (U, N, d), using only the first n[u] rows of model u (all rows if n is None).

        Statistics are computed in float64. A feature whose std is below `rel_floor` times the
        largest std of that model (a dead or constant channel) gets that floor instead, so
        standardising never divides by ~0.
        """
        x64 = x.double()
        U, N, _ = x.shape
        n = torch.full((U,), N, device=x.device) if n is None else n.to(x.device)
        if int(n.min()) < 1:
            raise ValueError("every model needs at least one row to fit a scaler")
        mask = (torch.arange(N, device=x.device) < n[:, None]).unsqueeze(-1)  # (U, N, 1)
        count = n.double().view(U, 1, 1)
        mean = (x64 * mask).sum(1, keepdim=True) / count
        var = (((x64 - mean) * mask) ** 2).sum(1, keepdim=True) / count
        std = var.sqrt()
        floor = (rel_floor * std.amax(-1, keepdim=True)).clamp_min(1e-12)
        return cls(mean.to(x.dtype), torch.maximum(std, floor).to(x.dtype))

    @classmethod
    def identity(cls, n_models: int, dim: int) -> Scaler:
        """A scaler that changes nothing."""
        return cls(torch.zeros(n_models, 1, dim), torch.ones(n_models, 1, dim))

    def transform(self, x: Tensor) -> Tensor:
        """Physical (U, B, d) -> standardised (U, B, d)."""
        return (x - self.mean) / self.std

    def inverse(self, z: Tensor) -> Tensor:
        """Standardised (U, B, d) -> physical (U, B, d)."""
        return z * self.std + self.mean

    def take(self, idx) -> Scaler:
        """The scalers of models idx (indices, a sequence or tensor): shapes (len(idx), 1, d).
        A one-model scaler (1, 1, d) taken at [0, 0, ...] repeats for every model."""
        idx = torch.as_tensor(idx, dtype=torch.long, device=self.mean.device)
        return Scaler(self.mean[idx], self.std[idx])

    def slice(self, i: int) -> Scaler:
        """The scaler of model i alone, shapes (1, 1, d)."""
        return Scaler(self.mean[i : i + 1].clone(), self.std[i : i + 1].clone())

    def to(self, device: torch.device | str) -> Scaler:
        return Scaler(self.mean.to(device), self.std.to(device))
