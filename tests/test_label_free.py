"""anytip.train.label_free: a unit's codes from unlabeled pressures alone."""

import torch

from anytip.models.response import ResponseConfig, ResponseModel
from anytip.train.label_free import LabelFreeRecipe, joint_fit, label_free_codes, nearest_contacts
from anytip.train.response import ResponseFit, ResponseRecipe


def _fit(seed: int = 1) -> ResponseFit:
    """A small random response model (3 training units, 8 barometers, 5 labels, force in 0-2)."""
    config = ResponseConfig(code_dim=4, channel_dim=4, hidden=32, layers=2)
    model = ResponseModel(3, 8, 5, [0, 1, 2], config, seed=seed)
    return ResponseFit(model, torch.full((8,), 1e-4), torch.full((4,), 0.04), ["a", "b", "c"])


def _contacts(n: int, seed: int) -> torch.Tensor:
    g = torch.Generator().manual_seed(seed)
    return torch.cat([torch.randn(n, 3, generator=g) * 5, torch.rand(n, 2, generator=g) - 0.5], 1)


def test_the_contact_search_finds_each_rows_contact_among_the_candidates():
    """Pressures made by the response model from candidate contacts under some codes are matched
    to exactly those contacts under the same codes, and mostly not under codes far from them."""
    fit, candidates = _fit(), _contacts(600, 0)
    codes = 0.3 * torch.randn(8, 4, generator=torch.Generator().manual_seed(2))
    with torch.no_grad():
        X = fit.model(candidates[:200], codes)
    assert torch.equal(nearest_contacts(fit, X, candidates, codes, chunk=64), candidates[:200])
    far = nearest_contacts(fit, X, candidates, codes + 3.0)
    assert (far != candidates[:200]).any(1).float().mean() > 0.5


def test_the_joint_fit_started_at_the_truth_stays_there_and_never_raises_its_objective():
    """Noiseless pressures of known codes and contacts: the joint fit started at them keeps them
    (a weak pull towards other contacts and the codes' prior move them little), and no step raises
    the objective; from the searched start its objective ends below where it began."""
    fit, truth_y = _fit(), _contacts(300, 3)
    codes = 0.2 * torch.randn(8, 4, generator=torch.Generator().manual_seed(4))
    with torch.no_grad():
        X = fit.model(truth_y, codes)
    wrong = truth_y + 0.5 * torch.randn(truth_y.shape, generator=torch.Generator().manual_seed(5))
    z, y, trace = joint_fit(fit, X, wrong, 300.0, 5, 1e-3, start=(codes, truth_y))
    rms = lambda t: float(t.pow(2).mean().sqrt())  # noqa: E731
    assert rms(z - codes) < 0.25 * rms(codes) and rms(y - truth_y) < 0.1 * rms(wrong - truth_y)
    assert all(b <= a for a, b in zip(trace, trace[1:], strict=False))
    free = LabelFreeRecipe(rows=300, candidates=600, rounds=2, iterations=10)
    candidates = torch.cat([truth_y, _contacts(300, 6)])
    z, y, trace = label_free_codes(fit, ResponseRecipe(), free, X, wrong, 300.0, candidates, 0)
    assert all(b <= a for a, b in zip(trace, trace[1:], strict=False))
    assert z.shape == codes.shape and y.shape == truth_y.shape and trace[-1] < trace[0]


def test_a_unit_without_unlabeled_rows_keeps_the_fleets_typical_codes():
    """No ordinary use read (no press outside the unit's test patches): codes zero, no fit."""
    fit = _fit()
    none = torch.zeros(0, 8)
    z, y, trace = label_free_codes(fit, ResponseRecipe(), LabelFreeRecipe(), none, torch.zeros(0, 5), 600.0,
                                   _contacts(50, 7), 0)
    assert torch.equal(z, torch.zeros(8, 4)) and y.shape == (0, 5) and trace == []
