"""FusedAdam: torch's fused Adam kernel without torch.optim's wrapper, the same updates bit for bit."""

import pytest
import torch

from anytip.train.fused_adam import FusedAdam, fused_kernel_serves
from anytip.train.recipe import FAST, make_optimizer, set_lr


def _weights(seed: int) -> list[torch.nn.Parameter]:
    g = torch.Generator().manual_seed(seed)
    return [torch.nn.Parameter(torch.randn(*shape, generator=g)) for shape in ((3, 8, 12), (3, 1, 12), (5,))]


@pytest.mark.parametrize(("decoupled", "weight_decay"), [(False, 0.0), (False, 0.01), (True, 0.05)])
def test_updates_equal_torch_fused_adam_bit_for_bit(decoupled, weight_decay):
    ours, theirs = _weights(0), _weights(0)
    opt = FusedAdam(ours, lr=1e-2, weight_decay=weight_decay, decoupled=decoupled)
    cls = torch.optim.AdamW if decoupled else torch.optim.Adam
    ref = cls(theirs, lr=1e-2, weight_decay=weight_decay, fused=True)
    g = torch.Generator().manual_seed(1)
    for step in range(25):
        lr = 1e-2 * (0.9**step)  # a schedule, set between steps as the training loops do
        set_lr(opt, lr)
        set_lr(ref, lr)
        for a, b in zip(ours, theirs, strict=True):
            grad = torch.randn(a.shape, generator=g)
            a.grad, b.grad = grad.clone(), grad.clone()
        ours[2].grad = theirs[2].grad = None if step % 5 == 3 else ours[2].grad  # skipped, as torch skips it
        opt.step()
        ref.step()
        for a, b in zip(ours, theirs, strict=True):
            assert torch.equal(a, b), f"step {step}"
    assert not torch.equal(ours[0], _weights(0)[0])  # it did update


def test_zero_grad_and_make_optimizer_choice():
    w = _weights(0)
    for p in w:
        p.grad = torch.ones_like(p)
    opt = make_optimizer(w, FAST)
    assert isinstance(opt, FusedAdam) and opt.param_groups[0]["lr"] == FAST.lr
    opt.zero_grad(set_to_none=False)
    assert all(torch.equal(p.grad, torch.zeros_like(p)) for p in w)
    opt.zero_grad()
    assert all(p.grad is None for p in w)
    double = [torch.nn.Parameter(torch.zeros(3, dtype=torch.float64))]
    assert not fused_kernel_serves(double) and isinstance(make_optimizer(double, FAST), torch.optim.Adam)
    with pytest.raises(ValueError, match="float32"):
        FusedAdam(double, lr=1e-3)


def test_a_gradient_in_another_layout_is_refused():
    """The kernel walks weight and gradient as flat memory: a transposed gradient would update the
    wrong elements, so it is refused rather than applied."""
    w = torch.nn.Parameter(torch.zeros(2, 4, 3))
    w.grad = torch.randn(2, 3, 4).transpose(1, 2)  # the right shape, another layout
    with pytest.raises(ValueError, match="layout"):
        FusedAdam([w], lr=1e-3).step()
    w.grad = w.grad.contiguous()
    FusedAdam([w], lr=1e-3).step()
    assert not torch.equal(w, torch.zeros(2, 4, 3))
