"""Adam and AdamW as torch's fused kernel, called without torch.optim's wrapper.

`torch.optim.Adam(fused=True)` runs one kernel, `torch._fused_adam_` (`_fused_adamw_` for AdamW),
over every weight. Around it the wrapper adds per-step bookkeeping (hooks, profiler records,
grouping by device; about 40-60 us of a tiny network's 0.6 ms step on a CPU core) and its first
construction imports `torch._dynamo` (1-1.6 s: most of a small fit's start). `FusedAdam` keeps the
same state and calls the same kernel with the same arguments, so its updates equal
`torch.optim.Adam(fused=True)`'s bit for bit (tests/test_fused_adam.py holds it to that).

Only what the project's training loops use: one parameter group whose `lr` the loop sets,
`step()` and `zero_grad(set_to_none=True)`; weights without a gradient are skipped, as torch
skips them. `make_optimizer` (train/recipe.py) picks it where every weight is float32 on a CPU or
CUDA device, the devices the fused kernel serves.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import torch
from torch import Tensor

FUSED_DEVICES = ("cpu", "cuda")
# weights, m, v, step counts (views into the last: one tensor holding the group's counts)
Group = tuple[list[Tensor], list[Tensor], list[Tensor], list[Tensor], Tensor]


def fused_kernel_serves(params: list[Tensor]) -> bool:
    """Whether torch's fused Adam kernel runs on every one of `params`: float32 on a CPU or CUDA device."""
    return bool(params) and all(p.device.type in FUSED_DEVICES and p.dtype == torch.float32 for p in params)


def _same_layout(a: Tensor, b: Tensor) -> bool:
    """Whether a and b lay their elements out in memory alike (strides of size-1 dimensions aside)."""
    return a.stride() == b.stride() or (a.is_contiguous() and b.is_contiguous())


class FusedAdam:
    """Adam (`decoupled=False`: weight decay added to the gradient) or AdamW (`decoupled=True`) on
    `params` at learning rate `lr`, betas (0.9, 0.999) and eps 1e-8, torch's defaults."""

    def __init__(self, params: Iterable[Tensor], lr: float, weight_decay: float = 0.0,
                 decoupled: bool = False, betas: tuple[float, float] = (0.9, 0.999), eps: float = 1e-8):
        self.params = list(params)
        if not fused_kernel_serves(self.params):
            raise ValueError("FusedAdam needs float32 weights on a CPU or CUDA device")
        self.param_groups: list[dict[str, Any]] = [{"params": self.params, "lr": lr}]
        self.kernel = torch._fused_adamw_ if decoupled else torch._fused_adam_
        self.weight_decay, self.betas, self.eps = weight_decay, betas, eps
        self.state: dict[Tensor, tuple[Tensor, Tensor, Tensor]] = {}  # weight -> (m, v, step)
        self._live: tuple[bool, ...] = ()  # which weights had a gradient at the last step
        self._groups: list[Group] = []

    def zero_grad(self, set_to_none: bool = True) -> None:
        for p in self.params:
            if set_to_none:
                p.grad = None
            elif p.grad is not None:
                p.grad.zero_()

    @torch.no_grad()
    def step(self) -> None:
        """One update of every weight that has a gradient, at the group's current `lr`."""
        live = tuple(p.grad is not None for p in self.params)
        if live != self._live:  # which weights take part changed (or the first step): regroup
            self._groups = self._group([p for p, has in zip(self.params, live, strict=True) if has])
            self._live = live
        lr = float(self.param_groups[0]["lr"])
        for group, m, v, steps, counts in self._groups:
            grads = [p.grad for p in group]
            if not all(_same_layout(g, p) for g, p in zip(grads, group, strict=True)):
                # the kernel walks weight and gradient as flat memory: another layout would update the
                # wrong elements without a word
                raise ValueError("a gradient's memory layout differs from its weight's (make it contiguous)")
            counts.add_(1)  # every weight's count at once: a third of `_foreach_add_` over 0-d counts
            self.kernel(group, grads, m, v, [], steps, amsgrad=False, lr=lr,
                        beta1=self.betas[0], beta2=self.betas[1], weight_decay=self.weight_decay,
                        eps=self.eps, maximize=False, grad_scale=None, found_inf=None)

    def _group(self, live: list[Tensor]) -> list[Group]:
        """Per device: the weights in `live`, their first and second moments and step counts (made
        as torch's first step makes them: zeros, a float32 count), the counts gathered into one tensor
        whose elements the weights' state then holds as views (a weight left out keeps its own)."""
        for p in live:
            if p not in self.state:
                self.state[p] = (torch.zeros_like(p, memory_format=torch.preserve_format),
                                 torch.zeros_like(p, memory_format=torch.preserve_format),
                                 torch.zeros((), dtype=torch.float32, device=p.device))
        groups = []
        for device in dict.fromkeys(p.device for p in live):
            on = [p for p in live if p.device == device]
            m, v, steps = (list(s) for s in zip(*(self.state[p] for p in on), strict=True))
            counts = torch.stack(steps)
            steps = list(counts.unbind())
            for p, mp, vp, step in zip(on, m, v, steps, strict=True):
                self.state[p] = (mp, vp, step)
            groups.append((on, m, v, steps, counts))
        return groups
