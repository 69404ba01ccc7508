"""anytip.train.label_free: a unit's codes from unlabeled pressures alone."""

import json
from dataclasses import asdict, replace

import numpy as np
import pytest
import torch

from anytip.models.response import ResponseConfig, ResponseModel
from anytip.train import label_free
from anytip.train.code_encoder import ENCODER_QUANTILES, PA_FLOOR, CodeEncoder, stream_features
from anytip.train.code_prior import CodePrior
from anytip.train.label_free import (
    FleetUse,
    ForceScale,
    Labeled,
    LabelFreeRecipe,
    distilled_rows,
    joint_fit,
    joint_objective,
    label_free_codes,
    mean_square_force,
    nearest_contacts,
    plan_and_use_codes,
    schur_step,
    searched_start,
    with_use_method,
)
from anytip.train.response import ResponseFit, ResponseRecipe, fit_codes


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


def test_the_search_starts_from_the_codes_it_is_given():
    """Pressures made under codes far from zero: a search without rounds started from those codes
    matches every row to its own contact and keeps the codes; started from codes zero it mostly
    does not."""
    fit, candidates = _fit(), _contacts(600, 0)
    codes = 3.0 + 0.3 * torch.randn(8, 4, generator=torch.Generator().manual_seed(2))
    with torch.no_grad():
        X = fit.model(candidates[:200], codes)
    z, y = searched_start(fit, ResponseRecipe(), X, 200.0, candidates, 0, 0, codes=codes)
    assert torch.equal(z, codes) and torch.equal(y, candidates[:200])
    z, y = searched_start(fit, ResponseRecipe(), X, 200.0, candidates, 0, 0)
    assert torch.equal(z, torch.zeros_like(codes)) and (y != candidates[:200]).any(1).float().mean() > 0.5


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


def test_labeled_rows_enter_the_joint_fit_as_the_codes_map_takes_them():
    """Labeled rows beside unlabeled ones that weigh almost nothing: the joint fit's codes are the
    codes' MAP on the labeled rows alone (`fit_codes`, the same loss), and its objective never rises;
    with the unlabeled rows weighing their own, the labeled rows still pull the codes to the truth."""
    fit, truth_y = _fit(), _contacts(200, 8)
    codes = 0.2 * torch.randn(8, 4, generator=torch.Generator().manual_seed(4))
    with torch.no_grad():
        X_l = fit.model(truth_y, codes)
        X = fit.model(_contacts(100, 9), codes)
    labeled = Labeled(X_l, truth_y, 200.0)
    alone = fit_codes(fit, [X_l], [truth_y], [200.0], ResponseRecipe())[0]
    z, _, trace = joint_fit(fit, X, _contacts(100, 10), 1e-6, 40, 1e-3, labeled=labeled)
    assert all(b <= a for a, b in zip(trace, trace[1:], strict=False))
    torch.testing.assert_close(z, alone, atol=2e-3, rtol=1e-2)
    rms = lambda t: float(t.pow(2).mean().sqrt())  # noqa: E731
    z, y, trace = joint_fit(fit, X, _contacts(100, 10), 100.0, 40, 1e-3, labeled=labeled)
    unlabeled_only, _, _ = joint_fit(fit, X, _contacts(100, 10), 100.0, 40, 1e-3)
    assert rms(z - codes) < 0.5 * rms(unlabeled_only - codes)
    # the objective the fit reads off its Jacobians' forward pass is the objective
    m = fit.model
    std_c = lambda t: (t - m.label_mean) / m.label_std  # noqa: E731
    at_end = joint_objective(fit, X, std_c(_contacts(100, 10)), 1.0, std_c(y), z, 1e-3, labeled=labeled)
    assert trace[-1] == pytest.approx(at_end, rel=1e-5)


def test_the_joint_fit_and_the_codes_map_hold_the_same_learnt_prior():
    """Under a prior with a mean away from zero and correlated dimensions (`train.code_prior`), the
    joint fit whose unlabeled rows weigh almost nothing ends at `fit_codes`' MAP of the labeled rows,
    and a unit without rows keeps the prior's mean."""
    g = torch.Generator().manual_seed(11)
    A = torch.randn(8, 4, 4, generator=g)
    prior = CodePrior(0.1 * torch.randn(8, 4, generator=g), 10 * (A @ A.transpose(1, 2) / 4 + torch.eye(4)))
    fit, truth_y = replace(_fit(), prior=prior), _contacts(200, 8)
    codes = 0.2 * torch.randn(8, 4, generator=g)
    with torch.no_grad():
        X_l = fit.model(truth_y, codes)
        X = fit.model(_contacts(100, 9), codes)
    alone = fit_codes(fit, [X_l], [truth_y], [20.0], replace(ResponseRecipe(), code_iterations=40))[0]
    plain = fit_codes(_fit(), [X_l], [truth_y], [20.0], replace(ResponseRecipe(), code_iterations=40))[0]
    assert float((alone - plain).abs().max()) > 1e-2  # the prior moves the MAP
    z, _, _ = joint_fit(fit, X, _contacts(100, 10), 1e-6, 40, 1e-3, labeled=Labeled(X_l, truth_y, 20.0))
    torch.testing.assert_close(z, alone, atol=2e-3, rtol=1e-2)
    none = torch.zeros(0, 8)
    z, _, _ = label_free_codes(fit, ResponseRecipe(), LabelFreeRecipe(), none, torch.zeros(0, 5), 600.0,
                               _contacts(50, 7), 0)
    assert torch.equal(z, prior.mean)


def test_a_unit_without_unlabeled_rows_keeps_the_fleets_typical_codes():
    """No ordinary use read (no press outside the unit's test patches): codes zero, no fit."""
    fit = _fit()
    none = torch.zeros(0, 8)
    z, y, trace = label_free_codes(fit, ResponseRecipe(), LabelFreeRecipe(), none, torch.zeros(0, 5), 600.0,
                                   _contacts(50, 7), 0)
    assert torch.equal(z, torch.zeros(8, 4)) and y.shape == (0, 5) and trace == []


def test_the_force_scale_prior_sets_how_hard_the_rows_are_pressed():
    """A tight prior on the rows' mean square force at 1.44 times the truth's: the joint fit started
    at the truth ends with its contacts' mean square force at the prior's (the rank-one term enters
    every step), its objective never rising; without the prior it stays near the truth's."""
    fit, truth_y = _fit(), _contacts(300, 3)
    codes = 0.2 * torch.randn(8, 4, generator=torch.Generator().manual_seed(4))
    with torch.no_grad():
        X = fit.model(truth_y, codes)
    m = mean_square_force(truth_y, (0, 1, 2))
    scale = ForceScale((0, 1, 2), 1.44 * m, (1e-3 * m) ** 2)
    _, y, trace = joint_fit(fit, X, truth_y, 300.0, 20, 1e-3, start=(codes, truth_y), scale=scale)
    assert abs(mean_square_force(y, (0, 1, 2)) / (1.44 * m) - 1) < 0.02
    assert all(b <= a for a, b in zip(trace, trace[1:], strict=False))
    _, y, _ = joint_fit(fit, X, truth_y, 300.0, 20, 1e-3, start=(codes, truth_y))
    assert abs(mean_square_force(y, (0, 1, 2)) / m - 1) < 0.05


def test_the_force_scale_prior_comes_from_the_training_units_ordinary_use():
    """Its mean and variance are over units' mean square forces; one unit cannot give a spread."""
    units = [torch.tensor([[3.0, 0, 4, 0, 0]]), torch.tensor([[0.0, 0, 1, 0, 0], [0, 0, 3, 0, 0]])]
    scale = ForceScale.from_units(units, (0, 1, 2))
    assert scale.mean == pytest.approx(15.0) and scale.var == pytest.approx(200.0)
    with pytest.raises(ValueError, match="at least two units"):
        ForceScale.from_units(units[:1], (0, 1, 2))


def test_the_eliminated_step_solves_the_whole_system():
    """The step by Schur complement and Sherman-Morrison equals a dense solve of the joint system,
    with and without the rank-one force-scale term."""
    g = torch.Generator().manual_seed(9)
    n, C, k, D = 7, 3, 2, 5
    spd = lambda *s: (lambda M: M @ M.transpose(-1, -2) + s[-1] * torch.eye(s[-1]))(  # noqa: E731
        torch.randn(*s, s[-1], generator=g, dtype=torch.float64))
    Hzz, Hcc = spd(C, k), spd(n, D)
    A = 0.3 * torch.randn(n, C * k, D, generator=g, dtype=torch.float64)
    gz, gc, u = (torch.randn(*s, generator=g, dtype=torch.float64) for s in ((C * k,), (n, D), (n, D)))
    for rank_one in (None, u):
        H = torch.block_diag(torch.block_diag(*Hzz), torch.block_diag(*Hcc))
        B = A.permute(1, 0, 2).reshape(C * k, n * D)
        H[: C * k, C * k :], H[C * k :, : C * k] = B, B.T
        if rank_one is not None:
            H[C * k :, C * k :] += torch.outer(rank_one.reshape(-1), rank_one.reshape(-1))
        dense = torch.linalg.solve(H, torch.cat([gz, gc.reshape(-1)]))
        dz, dc = schur_step(Hzz, gz, Hcc, gc, A, rank_one)
        assert torch.allclose(torch.cat([dz, dc.reshape(-1)]), dense, rtol=1e-9, atol=1e-9)


def test_a_searched_start_with_the_force_scale_prior_presses_as_hard_as_the_fleet():
    """The prior's scaling keeps each contact's force direction and other columns, and the searched
    start's contacts come out at the prior's mean square force."""
    fit, truth_y = _fit(), _contacts(200, 3)
    scale = ForceScale((0, 1, 2), 2.0 * mean_square_force(truth_y, (0, 1, 2)), 1.0)
    matched = scale.match(truth_y)
    assert torch.allclose(matched[:, :3], truth_y[:, :3] * 2**0.5)
    assert torch.equal(matched[:, 3:], truth_y[:, 3:])
    with torch.no_grad():
        X = fit.model(truth_y, torch.zeros(8, 4))
    _, y = searched_start(fit, ResponseRecipe(), X, 200.0, _contacts(400, 8), 0, 2, scale)
    assert mean_square_force(y, (0, 1, 2)) == pytest.approx(scale.mean, rel=1e-4)
    z, y = searched_start(fit, ResponseRecipe(), X, 200.0, _contacts(400, 8), 0, 0, scale)  # no rounds
    assert torch.equal(z, torch.zeros(8, 4))
    assert mean_square_force(y, (0, 1, 2)) == pytest.approx(scale.mean, rel=1e-4)


def test_the_code_encoder_recovers_a_linear_map_and_knows_when_features_say_nothing():
    """CodeEncoder: codes that are a linear function of the features
    are predicted for a new unit and explained almost wholly when left out; codes unrelated to the
    features are explained not at all, and the prediction falls back towards the fleet's mean."""
    g = np.random.default_rng(0)
    F = g.normal(size=(120, 6))
    W = g.normal(size=(6, 2 * 3))
    var = np.array([0.5, 1.0, 2.0])
    Z = (F @ W).reshape(120, 2, 3) * np.sqrt(var)
    enc = CodeEncoder.fit(F, Z, var)
    assert enc.loo_r2 > 0.99
    new = g.normal(size=6)
    np.testing.assert_allclose(enc(new).numpy(), ((new @ W).reshape(2, 3) * np.sqrt(var)), atol=0.05)
    noise = CodeEncoder.fit(F, g.normal(size=(120, 2, 3)), var)
    assert noise.loo_r2 < 0.05
    assert float(noise(new).abs().max()) < 0.5
    with pytest.raises(ValueError, match="across units"):
        CodeEncoder.fit(F[:1], Z[:1], var)


def test_the_stream_features_ignore_row_order_and_floor_quiet_barometers():
    """stream_features: the same for rows in any order; a barometer that never reads above noise
    gives log(PA_FLOOR) for every quantile and its spread."""
    g = np.random.default_rng(1)
    P = np.abs(g.normal(size=(500, 8))) * 5000.0
    P[:, 3] = 1.0
    f = stream_features(P)
    assert f.shape == (8 * 6 + 28,)
    np.testing.assert_allclose(stream_features(P[g.permutation(500)]), f, rtol=1e-12)
    quiet = [q * 8 + 3 for q in range(len(ENCODER_QUANTILES))] + [len(ENCODER_QUANTILES) * 8 + 3]
    np.testing.assert_allclose(f[quiet], np.log(PA_FLOOR))


def test_a_plans_rows_are_thinned_in_the_joint_fit_still_weighing_the_whole_plan():
    """Labeled.thinned: at most that many rows, evenly spaced, worth the same n_eff (None: all);
    `plan_and_use_codes` fits `plan_rows` of them: the same codes as the thinned rows handed in."""
    fit, y = _fit(), _contacts(300, 11)
    codes = 0.2 * torch.randn(8, 4, generator=torch.Generator().manual_seed(5))
    with torch.no_grad():
        X_l, X = fit.model(y, codes), fit.model(_contacts(80, 12), codes)
    plan = Labeled(X_l, y, 150.0)
    few = plan.thinned(50)
    assert len(few.X) == 50 and few.n_eff == 150.0 and plan.thinned(None) is plan
    assert torch.equal(few.Y[0], y[0]) and torch.equal(few.Y[-1], y[-1])
    start = fit_codes(fit, [X_l], [y], [150.0], ResponseRecipe())[0]
    args = (fit, ResponseRecipe())
    rest = (X, _contacts(80, 13), 80.0, _contacts(200, 14), 0)
    thin = LabelFreeRecipe(plan_iterations=5, plan_rows=50)
    whole = replace(thin, plan_rows=None)
    thinned = plan_and_use_codes(*args, thin, *rest, plan, start)[0]
    handed = plan_and_use_codes(*args, whole, *rest, few, start)[0]
    every = plan_and_use_codes(*args, whole, *rest, plan, start)[0]
    torch.testing.assert_close(thinned, handed)
    assert not torch.equal(thinned, every)
    # use_weight: the unlabeled rows worth that many times their n_eff, the same fit as their n_eff scaled
    heavier = plan_and_use_codes(*args, replace(whole, use_weight=4.0), *rest, plan, start)[0]
    scaled = plan_and_use_codes(*args, whole, X, rest[1], 4 * 80.0, *rest[3:], plan, start)[0]
    assert torch.equal(heavier, scaled) and not torch.equal(heavier, every)


def test_how_a_fleet_reads_ordinary_use_survives_json_and_a_bad_value_is_named():
    """FleetUse.to_json / from_json (a response model's metadata): the recipe, force scale and encoder
    read back predict the same; a missing, non-finite or misshapen entry raises naming its key."""
    g = np.random.default_rng(3)
    coder = CodeEncoder.fit(g.normal(size=(30, 6)), g.normal(size=(30, 2, 3)), np.array([0.5, 1.0, 2.0]))
    scale = ForceScale((0, 1, 2), 40.0, 9.0)
    fleet = FleetUse(LabelFreeRecipe(seconds=300, plan_rows=None), 10.0, scale, coder)
    values = json.loads(json.dumps(fleet.to_json()))
    back = FleetUse.from_json(values, 5)
    assert back.free == fleet.free and back.scale == fleet.scale and back.effective_hz == 10.0
    x = g.normal(size=6)
    torch.testing.assert_close(back.coder(x), coder(x))
    assert FleetUse.from_json({**values, "encoder": None, "force_scale": None}, 5).coder is None
    with pytest.raises(ValueError, match="reads 6 features"):
        coder(np.zeros(7))
    bad = {
        "encoder: weights: shape": ("encoder", {**values["encoder"], "weights": [[1.0]]}),
        "encoder: f_mean: not finite": ("encoder", {**values["encoder"], "f_mean": [float("nan")] * 6}),
        "encoder: scale: missing": ("encoder", {k: v for k, v in values["encoder"].items() if k != "scale"}),
        "force_scale: columns": ("force_scale", {**values["force_scale"], "columns": [0, 7]}),
        "force_scale: var": ("force_scale", {**values["force_scale"], "var": -1.0}),
        "recipe: start": ("recipe", {**values["recipe"], "start": "anywhere"}),
        "recipe: rows": ("recipe", {**values["recipe"], "rows": 2.5}),
        "recipe: seconds": ("recipe", {**values["recipe"], "seconds": 900}),
        "recipe: use_weight": ("recipe", {**values["recipe"], "use_weight": 0}),
        "recipe: unknown keys": ("recipe", {**values["recipe"], "extra": 1}),
        "effective_hz": ("effective_hz", 0),
    }
    for message, (key, value) in bad.items():
        with pytest.raises(ValueError, match=message):
            FleetUse.from_json({**values, key: value}, 5)
    with pytest.raises(ValueError, match="plan_rows"):
        replace(LabelFreeRecipe(), plan_rows=0)
    with pytest.raises(ValueError, match="recipe: plan_iterations"):
        FleetUse.from_json({**values, "recipe": {**values["recipe"], "plan_iterations": 0}}, 5)


def test_the_joint_fit_with_a_plan_takes_plan_iterations_steps_and_old_records_their_iterations(monkeypatch):
    """`plan_iterations` (entry 81): the joint fit with a plan's rows runs that many steps (default 10),
    or `iterations` where it is None; a recipe recorded before it existed reads None, so a saved model
    calibrates a unit with the steps its benchmark took."""
    assert LabelFreeRecipe().steps_with_plan() == 10
    assert LabelFreeRecipe(iterations=7, plan_iterations=None).steps_with_plan() == 7
    old = {k: v for k, v in asdict(LabelFreeRecipe(iterations=30)).items() if k != "plan_iterations"}
    assert LabelFreeRecipe.from_json(old).steps_with_plan() == 30
    assert LabelFreeRecipe.from_json(asdict(LabelFreeRecipe())).steps_with_plan() == 10
    steps = []
    real = label_free.joint_fit
    monkeypatch.setattr(label_free, "joint_fit", lambda *a, **k: (steps.append(a[4]), real(*a, **k))[1])
    fit, y = _fit(), _contacts(60, 11)
    codes = 0.2 * torch.randn(8, 4, generator=torch.Generator().manual_seed(5))
    with torch.no_grad():
        X_l, X = fit.model(y, codes), fit.model(_contacts(40, 12), codes)
    rest = (X, _contacts(40, 13), 40.0, _contacts(100, 14), 0, Labeled(X_l, y, 60.0), codes)
    for free in (LabelFreeRecipe(plan_iterations=3), LabelFreeRecipe(iterations=4, plan_iterations=None)):
        plan_and_use_codes(fit, ResponseRecipe(), free, *rest)
    assert steps == [3, 4]


@pytest.mark.parametrize("force_cols", [[0, 1, 2], []])
def test_the_models_jacobians_are_autograds_per_row(force_cols):
    """ResponseModel.jacobians: the pressures and their derivatives in each row's labels and in each
    barometer's own code equal forward-mode autograd's row by row, in float64 to its rounding, with
    and without a force target, and for a row pressed with no force (its magnitude's derivative taken
    as zero); codes shared by every row or one set per row."""
    config = ResponseConfig(code_dim=3, channel_dim=4, hidden=16, layers=2)
    model = ResponseModel(2, 6, 5, force_cols, config, seed=3).double()
    model.set_scales(_contacts(50, 1).double(), torch.rand(50, 6, dtype=torch.float64) * 1e4)
    y = _contacts(40, 2).double()
    y[0, :3] = 0.0
    codes = 0.3 * torch.randn(40, 6, 3, generator=torch.Generator().manual_seed(6), dtype=torch.float64)
    for z in (codes[0], codes):
        pressure, Jy, Jz = model.jacobians(y, z)
        zs = z.expand(40, 6, 3)
        want_y = torch.func.vmap(torch.func.jacfwd(lambda row, zr: model(row, zr)))(y[1:], zs[1:])
        want_z = torch.func.vmap(torch.func.jacfwd(lambda row, zr: model(row, zr), argnums=1))(y, zs)
        torch.testing.assert_close(pressure, model(y, z).detach(), rtol=0, atol=0)
        torch.testing.assert_close(Jy[1:], want_y.detach(), rtol=1e-10, atol=1e-9)
        torch.testing.assert_close(Jz, torch.diagonal(want_z, dim1=1, dim2=2).permute(0, 2, 1).detach(),
                                   rtol=1e-10, atol=1e-9)
        assert torch.isfinite(Jy[0]).all()
        off = want_z.detach().clone()
        off[:, torch.arange(6), torch.arange(6)] = 0  # a barometer's pressure reads no other's code
        assert off.abs().max() == 0


def test_the_joint_fit_takes_derivatives_only_where_a_step_starts(monkeypatch):
    """A refused trial costs its forward passes alone: the joint fit takes no derivatives at a trial
    it refuses and each point's at most once, and gives bit for bit what it gives when every trial's
    derivatives are taken at once."""
    fit, truth_y = _fit(), _contacts(120, 8)
    codes = 0.2 * torch.randn(8, 4, generator=torch.Generator().manual_seed(4))
    with torch.no_grad():
        X_l = fit.model(truth_y, codes)
        X = fit.model(_contacts(80, 9), codes)
    labeled, model = Labeled(X_l, truth_y, 120.0), fit.model
    plain, taken, forwards = type(model).linearisation, [], []

    def counted(self, labels, codes):
        pressure, derivatives = plain(self, labels, codes)
        forwards.append(len(forwards))
        mine = (len(forwards) - 1) // 2  # 0: the start; j: the trial of step j (unlabeled, then labeled rows)
        return pressure, lambda: (taken.append(mine), derivatives())[1]

    monkeypatch.setattr(type(model), "linearisation", counted)
    z, y, trace = joint_fit(fit, X, _contacts(80, 10), 80.0, 12, 1e-3, labeled=labeled)
    refused = [j for j in range(2, 13) if trace[j - 1] == trace[j - 2]]
    assert len(forwards) == 2 * 13 and refused  # else this test checks nothing
    assert not set(refused) & set(taken) and 0 in taken
    assert all(taken.count(p) == 2 for p in set(taken))  # once for each of the point's two passes

    def eager(self, labels, codes):
        pressure, derivatives = plain(self, labels, codes)
        both = derivatives()
        return pressure, lambda: both

    monkeypatch.setattr(type(model), "linearisation", eager)
    z2, y2, trace2 = joint_fit(fit, X, _contacts(80, 10), 80.0, 12, 1e-3, labeled=labeled)
    assert torch.equal(z, z2) and torch.equal(y, y2) and trace == trace2


def test_distilled_rows_repeat_the_use_with_fitted_or_true_contacts_and_a_bad_choice_is_named():
    """`distil` (entry 78): none adds nothing; fitted adds the pressures with the joint fit's contacts,
    oracle with the true ones, each `distil_repeat` times; oracle without true contacts and an unknown
    choice are refused by name; each choice has its own method name."""
    X, fitted, truth = torch.randn(7, 8), _contacts(7, 1), _contacts(7, 2)
    assert distilled_rows(LabelFreeRecipe(), X, fitted, truth) is None
    xs, ys = distilled_rows(LabelFreeRecipe(distil="fitted", distil_repeat=3), X, fitted, truth)
    assert xs.shape == (21, 8) and torch.equal(xs[14:], X) and torch.equal(ys[7:14], fitted)
    xs, ys = distilled_rows(LabelFreeRecipe(distil="oracle"), X, fitted, truth)
    assert torch.equal(xs, X) and torch.equal(ys, truth)
    with pytest.raises(ValueError, match="oracle needs the ordinary use's true contacts"):
        distilled_rows(LabelFreeRecipe(distil="oracle"), X, fitted)
    with pytest.raises(ValueError, match="distil: expected one of none, fitted, oracle, got 'off'"):
        LabelFreeRecipe(distil="off")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="distil_repeat: expected a whole number >= 1"):
        LabelFreeRecipe(distil_repeat=0)
    names = {with_use_method(LabelFreeRecipe(distil=d)) for d in ("none", "fitted", "oracle")}  # type: ignore[arg-type]
    assert names == {"response+use", "response+use+distil", "response+use+oracle"}


def test_the_search_reads_the_draw_its_recipe_names_and_draw_zero_is_the_seed_order():
    """`search_draw` (entry 219): draw 0 is the candidates every run before it searched (the run
    seed's order), another draw is another order of the same labels, the same for the same draw;
    a recipe recorded before the key existed reads draw 0, and a negative draw is refused."""
    labels = torch.arange(200, dtype=torch.float32)[:, None].repeat(1, 5)
    g = torch.Generator().manual_seed(7)
    seed_order = labels[torch.randperm(200, generator=g)[:50]]
    assert torch.equal(label_free.search_candidates(labels, 50, 7), seed_order)
    one, again = (label_free.search_candidates(labels, 50, 7, draw=1) for _ in range(2))
    assert torch.equal(one, again)
    assert not torch.equal(one, label_free.search_candidates(labels, 50, 7))
    assert set(one[:, 0].tolist()) <= set(range(200)) and len(set(one[:, 0].tolist())) == 50
    old = {k: v for k, v in asdict(LabelFreeRecipe()).items() if k != "search_draw"}
    assert LabelFreeRecipe.from_json(old).search_draw == 0
    with pytest.raises(ValueError, match="search_draw"):
        LabelFreeRecipe(search_draw=-1)


def test_starts_average_the_codes_of_the_draws_in_turn():
    """`starts` (entry 220): the label-free fit runs once per draw, from `search_draw` on, and the unit
    takes the mean of their codes; one start is `label_free_codes` itself."""
    fit, labels = _fit(), _contacts(400, 21)
    codes = 0.2 * torch.randn(8, 4, generator=torch.Generator().manual_seed(3))
    with torch.no_grad():
        X = fit.model(_contacts(60, 22), codes)
    Y0, free = _contacts(60, 23), LabelFreeRecipe(rows=60, candidates=100, rounds=1, iterations=3, starts=3,
                                                   search_draw=2)
    draws = label_free.search_draws(labels, free, 5)
    assert len(draws) == 3 and torch.equal(draws[0], label_free.search_candidates(labels, 100, 5, 2))
    assert torch.equal(draws[2], label_free.search_candidates(labels, 100, 5, 4))
    z, c, finals = label_free.started_codes(fit, ResponseRecipe(), free, X, Y0, 60.0, draws, 5)
    each = [label_free_codes(fit, ResponseRecipe(), free, X, Y0, 60.0, d, 5) for d in draws]
    assert torch.allclose(z, torch.stack([e[0] for e in each]).mean(0))
    assert torch.equal(c, each[0][1]) and finals == [e[2][-1] for e in each]
    one = label_free.started_codes(fit, ResponseRecipe(), free, X, Y0, 60.0, draws[:1], 5)
    assert torch.equal(one[0], each[0][0])
    with pytest.raises(ValueError, match="starts"):
        LabelFreeRecipe(starts=0)


def test_final_scale_refits_the_codes_to_the_fits_contacts_at_the_priors_scale():
    """`final_scale` (entry 223, on by default): the fit's contacts are scaled to the prior's mean square
    force, the codes are the MAP given them, the objective is still the fit's; without a prior nothing
    changes; a recipe recorded before the key existed reads false, and a value not true or false is
    refused."""
    fit, labels = _fit(), _contacts(400, 31)
    codes = 0.2 * torch.randn(8, 4, generator=torch.Generator().manual_seed(4))
    with torch.no_grad():
        X = fit.model(_contacts(60, 32), codes)
    Y0, candidates = _contacts(60, 33), label_free.search_candidates(labels, 100, 6)
    scale, recipe = ForceScale((0, 1, 2), 30.0, 4.0), ResponseRecipe()
    plain = LabelFreeRecipe(rows=60, candidates=100, rounds=1, iterations=3, final_scale=False)
    z0, c0, trace0 = label_free_codes(fit, recipe, plain, X, Y0, 60.0, candidates, 6, scale)
    z, c, trace = label_free_codes(fit, recipe, replace(plain, final_scale=True), X, Y0, 60.0, candidates, 6,
                                   scale)
    assert trace == trace0
    assert mean_square_force(c, (0, 1, 2)) == pytest.approx(30.0, rel=1e-5)
    assert mean_square_force(c0, (0, 1, 2)) != pytest.approx(30.0, rel=1e-3)
    assert torch.allclose(c, scale.match(c0))
    assert torch.allclose(z, fit_codes(fit, [X], [scale.match(c0)], [60.0], recipe, 6)[0])
    unscaled = label_free_codes(fit, recipe, replace(plain, final_scale=True), X, Y0, 60.0, candidates, 6)
    assert torch.equal(unscaled[0], label_free_codes(fit, recipe, plain, X, Y0, 60.0, candidates, 6)[0])
    old = {k: v for k, v in asdict(LabelFreeRecipe()).items() if k != "final_scale"}
    assert LabelFreeRecipe.from_json(old).final_scale is False and LabelFreeRecipe().final_scale is True
    with pytest.raises(ValueError, match="final_scale: expected true or false"):
        LabelFreeRecipe(final_scale=1)  # type: ignore[arg-type]
