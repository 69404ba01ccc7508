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

        Statistics are computed in float64, a block of rows at a time (`_row_sums`), so memory
        beyond x stays bounded. A feature whose std is below `rel_floor` times the largest std of
        that model (a dead or constant channel) gets that floor instead, so standardising never
        divides by ~0.
        """
        n = _row_counts(x, n)
        count = n.double().view(-1, 1, 1)
        mean = _row_sums(x, n) / count
        var = _row_sums(x, n, mean) / count
        return cls._floored(mean, var, rel_floor, x.dtype)

    @classmethod
    def pooled(cls, x: Tensor, n: Tensor | None = None, rel_floor: float = 1e-6) -> Scaler:
        """One scaler (1, 1, d) over the first n[u] rows of every model u of x (U, N, d), as `fit`
        on those rows stacked into one model, without stacking them."""
        n = _row_counts(x, n)
        count = n.double().sum()
        mean = _row_sums(x, n).sum(0, keepdim=True) / count
        var = _row_sums(x, n, mean).sum(0, keepdim=True) / count
        return cls._floored(mean, var, rel_floor, x.dtype)

    @classmethod
    def _floored(cls, mean: Tensor, var: Tensor, rel_floor: float, dtype: torch.dtype) -> Scaler:
        """The scaler of float64 mean and var (U, 1, d), each std floored at `rel_floor` of its
        model's largest."""
        std = var.sqrt()
        floor = (rel_floor * std.amax(-1, keepdim=True)).clamp_min(1e-12)
        return cls(mean.to(dtype), torch.maximum(std, floor).to(dtype))

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


ELEMENTS_PER_PASS = 1 << 22  # float64 numbers `_row_sums` converts at once (32 MB)


def _row_counts(x: Tensor, n: Tensor | None) -> Tensor:
    """(U,) rows of each model of x (U, N, d) to read: n, or N for every model where n is None."""
    U, N, _ = x.shape
    n = torch.full((U,), N, device=x.device) if n is None else n.to(x.device)
    if U == 0 or int(n.min()) < 1:
        raise ValueError("every model needs at least one row to fit a scaler")
    return n


def _row_sums(x: Tensor, n: Tensor, centre: Tensor | None = None) -> Tensor:
    """(U, 1, d) float64: over the first n[u] rows of each model u of x (U, N, d), the sum of x, or
    of (x - centre)^2 where centre (U or 1, 1, d) is given; a block of rows at a time."""
    U, N, d = x.shape
    step = max(1, ELEMENTS_PER_PASS // max(1, U * d))
    total = torch.zeros(U, 1, d, dtype=torch.float64, device=x.device)
    for a in range(0, int(n.max()), step):
        block = x[:, a : a + step].double()
        if centre is not None:
            block = (block - centre) ** 2
        rows = torch.arange(a, a + block.shape[1], device=x.device)
        total += torch.where((rows < n[:, None]).unsqueeze(-1), block, 0.0).sum(1, keepdim=True)
    return total
