"""Calibration by response transfer: the response model, a new unit's codes, the transfer of rows,
the saved model file, and the cross_sensor method `response` end to end on tiny fleets."""

import argparse
import importlib
import json
import multiprocessing
import re
import shutil
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np
import pytest
import torch

import anytip.train.response as response_module
from anytip.calibrate import calibrate_unit, response_strategy
from anytip.cli import main
from anytip.data.arrays import load_arrays
from anytip.data.calibration import calibration_stream
from anytip.data.plans import Budget, RigTiming, find_presses, select_presses
from anytip.data.registry import Registry
from anytip.data.simulated import simulate_flat_into
from anytip.errors import AnytipError
from anytip.models.io import ModelFileError, load_models, load_response, save_response
from anytip.models.mlp import MLPConfig
from anytip.models.response import ResponseConfig, ResponseModel
from anytip.pipelines.cross_sensor_response import fleet_groups
from anytip.runner import run_experiment
from anytip.sensor import flat
from anytip.train.data import FleetBatchData, UnitTensors
from anytip.train.fleet import joined_fits
from anytip.train.metrics import predict
from anytip.train.response import (
    PlanMisfit,
    ResponseFit,
    ResponseRecipe,
    SourceRows,
    calibrate_by_response,
    code_covariance,
    drawn_codes,
    fit_codes,
    plan_correction,
    plan_misfit,
    press_information,
    residual_rms,
    source_rows,
    train_response,
    transfer,
    transferred,
)
from anytip.uncertainty.fleet_margin import Learner, pooled_factor
from run_factory import make_run
from test_cross_sensor import REPO, SECONDS, SPEC
from test_plans import fleet as press_fleet

C, D = 4, 5  # barometers; labels: a 3-component force, then two place coordinates
SMALL = ResponseConfig(code_dim=2, channel_dim=3, hidden=32, layers=2)
FAST_FIT = ResponseRecipe(steps=1500, rows_per_step=1024, lr=1e-2, code_steps=300, code_rows=256,
                          source_rows=200, inverse_epochs=2)


def labels(n: int, g: torch.Generator) -> torch.Tensor:
    """(n, 5): a pressing force (N, fz < 0) with some shear, and a place in [-1, 1]^2."""
    force = torch.randn(n, 3, generator=g) * torch.tensor([2.0, 2.0, 4.0]) - torch.tensor([0.0, 0.0, 8.0])
    return torch.cat([force, 2 * torch.rand(n, 2, generator=g) - 1], 1)


def unit_pressures(y: torch.Tensor, gain: torch.Tensor, shift: torch.Tensor) -> torch.Tensor:
    """(n, C) Pa of a made-up unit: barometer c at place c/2 - 0.75 + shift[c], gain[c]; the
    pressure falls off with distance from the contact and grows with the normal force."""
    centre = torch.arange(C) / 2 - 0.75 + shift
    dist2 = (y[:, 3:4] - centre) ** 2 + y[:, 4:5] ** 2
    return -1000 * gain * y[:, 2:3] / (1 + 4 * dist2)


def made_up_fleet(n_units: int, seed: int) -> tuple[FleetBatchData, list[tuple[torch.Tensor, torch.Tensor]]]:
    """Units that differ in each barometer's gain and place (two numbers per barometer), their rows
    (2000 fitting, 200 validating), and the (gain, shift) of each."""
    g = torch.Generator().manual_seed(seed)
    members, params = [], []
    for u in range(n_units):
        gain, shift = 1 + 0.3 * torch.randn(C, generator=g), 0.2 * torch.randn(C, generator=g)
        y = labels(2200, g)
        x = unit_pressures(y, gain, shift) + 5 * torch.randn(2200, C, generator=g)
        members.append(UnitTensors(x[:2000], y[:2000], x[2000:], y[2000:], f"U{u}"))
        params.append((gain, shift))
    return FleetBatchData.from_units(members), params


@pytest.fixture(scope="module")
def made_up() -> tuple:
    data, params = made_up_fleet(12, seed=0)
    torch.manual_seed(0)
    return data, params, train_response(data, [0, 1, 2], SMALL, FAST_FIT, seed=0)


def test_the_response_takes_every_batch_shape_and_reads_zero_without_force():
    model = ResponseModel(3, C, D, [0, 1, 2], SMALL)
    g = torch.Generator().manual_seed(1)
    y = labels(10, g)
    codes = torch.randn(3, C, SMALL.code_dim, generator=g)
    assert model(y, codes[0]).shape == (10, C)
    batched = model(y.expand(3, 10, D), codes[:, None])
    assert batched.shape == (3, 10, C)
    torch.testing.assert_close(batched[1], model(y, codes[1]))
    still = y.clone()
    still[:, :3] = 0  # no force: a tared barometer reads nothing, wherever the place
    assert model(still, codes[0]).abs().max() == 0
    plain = ResponseModel(3, C, 2, [], SMALL)  # an edge sensor's targets: no force vector
    assert plain(y[:, 3:], codes[0]).shape == (10, C)


def map_loss(fit, X, Y, n_effective, codes) -> float:
    """The MAP objective `fit_codes` minimises, for one job."""
    with torch.no_grad():
        err = (X - fit.model(Y, codes)).pow(2) / fit.noise_var
    return float(n_effective / 2 * err.mean(0).sum() + (codes.pow(2) / fit.code_var).sum() / 2)


@pytest.mark.parametrize("solver", ["gauss_newton", "adam"])
def test_a_new_units_codes_from_its_rows_predict_its_other_rows(made_up, solver):
    data, _, fit = made_up
    new, _ = made_up_fleet(2, seed=99)  # units the response model never saw
    calib = [new.unit(u) for u in range(2)]
    X = [c.X_train[:300] for c in calib]
    Y = [c.Y_train[:300] for c in calib]
    recipe = replace(FAST_FIT, code_fit=solver)
    codes = fit_codes(fit, X, Y, [30.0, 30.0], recipe)
    for u, c in enumerate(calib):
        fitted = residual_rms(fit, c.X_val, c.Y_val, codes[u])
        typical = residual_rms(fit, c.X_val, c.Y_val, torch.zeros_like(codes[u]))
        assert fitted.mean() < 0.1 * typical.mean()
    none = fit_codes(fit, [X[0][:0]], [Y[0][:0]], [0.0], recipe)
    assert none.abs().max() == 0  # no calibration: the fleet's typical unit
    assert all(p.requires_grad for p in fit.model.parameters())  # the network is frozen only while fitting


def test_a_press_tells_the_codes_what_the_gauss_newton_step_weighs_from_its_labels_alone(made_up):
    _, _, fit = made_up
    arrays = press_fleet()  # 5 label columns (a force, two angles) as the made-up fleet's
    presses = find_presses(arrays, "U1")
    info = press_information(fit, arrays, presses, effective_hz=10.0)
    arrays.pressure[:] = np.nan  # the rig's labels say what a press tells; its pressures are never read
    again = press_information(fit, arrays, presses, effective_hz=10.0)
    assert np.array_equal(again.per_press, info.per_press)
    C, k = fit.model.n_channels, fit.model.config.code_dim
    assert info.per_press.shape == (len(presses), C, k, k) and info.criterion == "v"
    assert np.allclose(info.prior, fit.code_prior.precision.numpy())
    for p in (0, len(presses) - 1):
        rows = presses.rows_of(p)[np.linspace(0, len(presses.rows_of(p)) - 1, 8).round().astype(int)]
        y = torch.from_numpy(arrays.targets[rows])
        outer = torch.zeros(C, k, k)
        for row in y:
            for c in range(C):
                def pressure(z, c=c, row=row):
                    return fit.model(row, z)[c]
                J = torch.autograd.functional.jacobian(pressure, fit.code_prior.mean)[c]
                outer[c] += torch.outer(J, J) / fit.noise_var[c]
        n_eff = min(len(presses.rows_of(p)), presses.duration_s[p] * 10.0)
        assert np.allclose(info.per_press[p], (outer / len(y) * n_eff).numpy(), rtol=1e-4, atol=1e-9)
    bound = k * np.finfo(np.float32).eps * np.abs(info.region).max()  # float32 outer products, averaged
    assert np.linalg.eigvalsh(info.region).min() >= -bound


def test_a_press_tells_the_codes_of_a_response_without_a_force_target():
    """A sensor model whose targets hold no force (the response's plain output): each press's
    information is finite and positive semi-definite, and an informative plan is made from it."""
    arrays = press_fleet()
    presses = find_presses(arrays, "U1")
    model = ResponseModel(3, 4, arrays.targets.shape[1], [], SMALL, seed=1)
    fit = ResponseFit(model, torch.ones(4), torch.ones(SMALL.code_dim), ["A", "B", "C"])
    info = press_information(fit, arrays, presses, effective_hz=10.0)
    assert np.isfinite(info.per_press).all() and info.per_press.any()
    # sums of float32 outer products: PSD up to float32 rounding of each of the k x k entries
    bound = SMALL.code_dim * np.finfo(np.float32).eps * np.abs(info.per_press).max()
    assert np.linalg.eigvalsh(info.per_press).min() >= -bound
    plan = select_presses(presses, 40.0, strategy="cover_informative", information=info)
    assert 0 < plan.calib_seconds <= 40.0


def test_gauss_newton_reaches_the_map_estimate_at_least_as_well_as_adam(made_up):
    """Each barometer's code is a small least-squares problem: a few damped Gauss-Newton steps
    reach a loss no higher than 300 Adam steps, and more rows or steps no longer lower it."""
    _, _, fit = made_up
    new, _ = made_up_fleet(3, seed=98)
    X = [new.unit(u).X_train[:400] for u in range(3)]
    Y = [new.unit(u).Y_train[:400] for u in range(3)]
    n_eff = [40.0, 40.0, 400.0]
    adam = fit_codes(fit, X, Y, n_eff, replace(FAST_FIT, code_fit="adam"))
    newton = fit_codes(fit, X, Y, n_eff, replace(FAST_FIT, code_fit="gauss_newton", code_rows=400))
    longer = fit_codes(fit, X, Y, n_eff, replace(FAST_FIT, code_fit="gauss_newton", code_rows=400,
                                                 code_iterations=40))
    for m in range(3):
        best = map_loss(fit, X[m], Y[m], n_eff[m], longer[m])
        assert map_loss(fit, X[m], Y[m], n_eff[m], newton[m]) <= 1.001 * best
        assert map_loss(fit, X[m], Y[m], n_eff[m], newton[m]) <= map_loss(fit, X[m], Y[m], n_eff[m], adam[m])


def test_a_code_fit_with_a_tolerance_stops_each_barometer_near_its_optimum_on_its_own(made_up, monkeypatch):
    """A unit whose barometers read three times the fleet's gain starts far from its optimum: with a
    tolerance its fit stops long before 200 steps, at the 200-step loss; an ordinary unit stops
    sooner, and fitted in one pass with the far unit it keeps the codes it gets alone."""
    _, _, fit = made_up
    g = torch.Generator().manual_seed(5)
    y = labels(400, g)
    far = unit_pressures(y, torch.full((C,), 3.0), torch.tensor([0.3, -0.3, 0.3, -0.3]))
    far = far + 5 * torch.randn(400, C, generator=g)
    new, _ = made_up_fleet(1, seed=98)
    X, Y = [far, new.unit(0).X_train[:400]], [y, new.unit(0).Y_train[:400]]
    steps = []
    system = response_module._PlanProblem.system
    monkeypatch.setattr(response_module._PlanProblem, "system",
                        lambda self, *a: steps.append(1) or system(self, *a))

    def fitted(jobs: list[int], **recipe) -> tuple[torch.Tensor, int]:
        steps.clear()
        codes = fit_codes(fit, [X[j] for j in jobs], [Y[j] for j in jobs], [400.0] * len(jobs),
                          replace(FAST_FIT, code_rows=400, code_iterations=200, **recipe))
        return codes, len(steps)

    fixed, n_fixed = fitted([0])
    stopped, n_far = fitted([0], code_tolerance=1e-6)
    assert n_fixed == 200 and n_far < 50
    assert map_loss(fit, X[0], Y[0], 400.0, stopped[0]) <= 1.0001 * map_loss(fit, X[0], Y[0], 400.0, fixed[0])
    _, n_ordinary = fitted([1], code_tolerance=1e-6)
    assert n_ordinary < n_far
    # a coarse tolerance stops the ordinary unit at 4 steps, the far one at 7: the ordinary unit's
    # codes stay where it stopped (steps past it would move them, if only in the last digits)
    alone, n_ordinary = fitted([1], code_tolerance=0.1)
    both, n_both = fitted([0, 1], code_tolerance=0.1)
    assert n_ordinary < n_both
    assert torch.equal(both[1], alone[0])


def test_a_plans_correction_carries_a_misfit_its_codes_cannot_to_the_transferred_rows(made_up):
    """A new unit whose barometers also read a smooth bump over the place, which no code of the
    fleet's response gives: the correction learnt from its plan's residuals predicts most of that
    misfit on other rows, falls to zero far from every press, and is what `transferred` adds to
    `transfer` (nothing without a kernel length). Its query rows' kernel in float32 stays within the
    rounding bound of float64's (`float32_kernel_bound`)."""
    data, _, fit = made_up
    g = torch.Generator().manual_seed(7)
    y = labels(1300, g)
    bump = 300 * torch.sin(3 * y[:, 3:4]) * torch.tensor([1.0, -1.0, 0.5, 2.0])
    x = unit_pressures(y, 1 + 0.2 * torch.randn(C, generator=g), 0.1 * torch.randn(C, generator=g))
    x = x + bump + 5 * torch.randn(1300, C, generator=g)
    plan, other = slice(0, 300), slice(300, 1300)
    codes = fit_codes(fit, [x[plan]], [y[plan]], [300.0], FAST_FIT)[0]
    recipe = replace(FAST_FIT, residual_length=1.0, residual_ratio=0.01, residual_rows=300)
    scale = (y.double().mean(0), y.double().std(0))
    misfit = x[other] - fit.model(y[other], codes).detach()
    corrected = misfit - plan_correction(fit, x[plan], y[plan], codes, y[other], scale, recipe)
    assert corrected.pow(2).mean().sqrt() < 0.5 * misfit.pow(2).mean().sqrt()
    exact = plan_correction(fit, x[plan], y[plan], codes, y[other], scale, recipe, torch.float64)
    assert not torch.equal(misfit - corrected, exact)  # the float32 query kernel is the default
    assert ((misfit - corrected - exact).abs() <= float32_kernel_bound(
        plan_misfit(fit, x[plan], y[plan], codes, scale, recipe), y[other], recipe.residual_length)
        + 2**-24 * exact.abs()).all()
    far = y[other][:5].clone()
    far[:, 3:] = 40.0  # a place no press came near
    assert plan_correction(fit, x[plan], y[plan], codes, far, scale, recipe).abs().max() < 1e-6
    source = source_rows(fit, data, 50)
    source_scale = (source.Y.double().mean(0), source.Y.double().std(0))
    carried = transferred(fit, source, codes, x[plan], y[plan], recipe)
    added = plan_correction(fit, x[plan], y[plan], codes, source.Y, source_scale, recipe)
    assert torch.allclose(carried, transfer(fit, source, codes) + added, atol=1e-3)
    assert added.abs().max() > 10
    off = transferred(fit, source, codes, x[plan], y[plan], FAST_FIT)
    assert torch.equal(off, transfer(fit, source, codes))


def unit_network_output(fit: ResponseFit, source: SourceRows, X: list[torch.Tensor], Y: list[torch.Tensor],
                        n_effective: list[float], recipe: ResponseRecipe, probe: torch.Tensor,
                        codes: torch.Tensor | None = None) -> torch.Tensor:
    """(n, D): the first job's network of `calibrate_by_response` (a small 16-wide shape) at `probe`
    (1, n, C) Pa, its codes fitted on its plan or given."""
    nets, _ = calibrate_by_response(fit, source, X, Y, n_effective, MLPConfig(sizes=(C, 16, 5)), recipe,
                                    codes=codes)
    return predict(nets.model, nets.in_scaler, nets.out_scaler, probe)[0]


def test_a_centred_correction_leaves_the_plan_sessions_offset_out(made_up):
    """A plan whose rows read the unit's response with given codes plus an offset per barometer (its own
    session's, against codes fitted with its ordinary use): the correction as it was learnt (`kept`) carries
    that offset to rows near its presses; `centred` learns the residuals less their mean, so a pure offset
    gives none. `calibrate_by_response` centres where the codes are given and the recipe says so, and
    nowhere else."""
    data, _, fit = made_up
    g = torch.Generator().manual_seed(11)
    y = labels(300, g)
    codes = 0.3 * torch.randn(C, fit.model.config.code_dim, generator=g)
    offset = torch.tensor([200.0, -150.0, 80.0, 300.0])
    x = fit.model(y, codes).detach() + offset
    recipe = replace(FAST_FIT, residual_length=1.0, residual_ratio=0.01, residual_rows=300)
    scale = (y.double().mean(0), y.double().std(0))
    kept = plan_correction(fit, x, y, codes, y[:50], scale, recipe)
    assert (kept.mean(0) / offset > 0.5).all()
    assert plan_correction(fit, x, y, codes, y[:50], scale, recipe, centred=True).abs().max() < 1e-3
    source = source_rows(fit, data, 50, seed=0)
    probe = x[None, :30]

    def predicted(level: str, given: torch.Tensor | None) -> torch.Tensor:
        return unit_network_output(fit, source, [x], [y], [30.0], replace(recipe, residual_level=level),
                                   probe, given)

    assert not torch.equal(predicted("kept", codes[None]), predicted("centred", codes[None]))
    assert torch.equal(predicted("kept", None), predicted("centred", None))


def float32_kernel_bound(misfit: PlanMisfit, queries: torch.Tensor, length: float) -> torch.Tensor:
    """(q, C): how far `plan_correction`'s float32 evaluation at `queries` (q, D) may lie from its float64
    one, by float32 rounding (u = 2^-24) of each step: the standardised contacts a and points p rounded
    (u each) and the squared distance |a|^2 + |p|^2 - 2 a.p over D coordinates, at most (2D + 8) u
    (|a| + |p|)^2; the exponent's division (u |d2| / 2l^2) and exp's own two ulps; the product with the
    rounded weights over n points, (n + 4) u sum |K w|. Each term times the kernel K and |w|, summed over
    the points, with 1% to spare for second-order terms."""
    u, (n, d) = 2.0**-24, misfit.points.shape
    a = (queries.double() - misfit.mean) / misfit.std
    d2 = torch.cdist(a, misfit.points) ** 2
    k = torch.exp(-d2 / (2 * length**2))
    reach = (a.norm(dim=1, keepdim=True) + misfit.points.norm(dim=1)) ** 2
    relative = (2 * d + 8) * u * reach / (2 * length**2) + u * d2 / (2 * length**2) + (n + 4) * u
    return 1.01 * (k * relative) @ misfit.weights.abs()


@pytest.mark.parametrize("solver", ["gauss_newton", "adam"])
def test_codes_fitted_under_a_learnt_prior_reach_its_map_and_keep_its_mean_without_rows(made_up, solver):
    """Under each barometer's own prior (mean away from zero, correlated dimensions) the fit reaches
    that objective's minimum; with almost no weight on the rows it stays at the prior's mean, and a
    job without rows keeps it."""
    data, _, fit = made_up
    registry = [str(u) for u in data.unit_ids[:6]]
    learnt = fit.with_code_prior("registry", registry)
    prior = learnt.code_prior
    assert prior.mean.abs().max() > 0 and (prior.precision - torch.diag_embed(
        torch.diagonal(prior.precision, dim1=-2, dim2=-1))).abs().max() > 0
    new, _ = made_up_fleet(1, seed=97)
    X, Y = [new.unit(0).X_train[:400]], [new.unit(0).Y_train[:400]]

    def loss(codes: torch.Tensor, n_eff: float) -> float:
        with torch.no_grad():
            err = (X[0] - fit.model(Y[0], codes)).pow(2) / fit.noise_var
        return float(n_eff / 2 * err.mean(0).sum() + prior.penalty(codes).sum())

    recipe = replace(FAST_FIT, code_fit=solver, code_rows=400)
    codes = fit_codes(learnt, X, Y, [40.0], recipe)[0]
    longer = fit_codes(learnt, X, Y, [40.0], replace(recipe, code_fit="gauss_newton", code_iterations=40))[0]
    assert loss(codes, 40.0) <= (1.001 if solver == "gauss_newton" else 1.05) * loss(longer, 40.0)
    assert loss(longer, 40.0) < loss(fit_codes(fit, X, Y, [40.0], recipe)[0], 40.0)  # not the diagonal's MAP
    held = fit_codes(learnt, X, Y, [1e-6], replace(recipe, code_fit="gauss_newton"))[0]
    torch.testing.assert_close(held, prior.mean, atol=1e-3, rtol=0)
    none = fit_codes(learnt, [X[0][:0]], [Y[0][:0]], [0.0], recipe)[0]
    torch.testing.assert_close(none, prior.mean)


def test_the_codes_covariance_is_the_inverse_gauss_newton_hessian_and_shrinks_with_rows(made_up):
    """`code_covariance`: per barometer, the inverse of the prior's precision plus the plan's rows'
    J J^T at their weight (J by autograd, row by row); more rows leave less; no rows, the prior's."""
    _, _, fit = made_up
    new, _ = made_up_fleet(1, seed=96)
    X, Y = new.unit(0).X_train[:60], new.unit(0).Y_train[:60]
    recipe = replace(FAST_FIT, code_rows=60)
    codes = fit_codes(fit, [X, X[:6], X[:0]], [Y, Y[:6], Y[:0]], [30.0, 3.0, 0.0], recipe)
    cov = code_covariance(fit, [X, X[:6], X[:0]], [Y, Y[:6], Y[:0]], [30.0, 3.0, 0.0], codes, recipe)
    C, k = fit.model.n_channels, fit.model.config.code_dim
    for c in range(C):
        def pressure_c(z: torch.Tensor, y: torch.Tensor, c: int = c) -> torch.Tensor:
            full = codes[0].clone()
            full[c] = z
            return fit.model(y[None], full)[0, c]

        H = fit.code_prior.precision[c].clone()
        for y in Y:
            J = torch.autograd.functional.jacobian(lambda z, y=y: pressure_c(z, y), codes[0, c])
            H = H + 30.0 / 60 / fit.noise_var[c] * torch.outer(J, J)
        torch.testing.assert_close(cov[0, c], torch.linalg.inv(H), rtol=1e-3, atol=1e-7)
    assert (torch.linalg.det(cov[0]) < torch.linalg.det(cov[1])).all()
    torch.testing.assert_close(cov[2], torch.linalg.inv(fit.code_prior.precision).expand(C, k, k))


def test_codes_drawn_for_the_transferred_rows_follow_their_posterior_and_only_where_fitted(made_up):
    """`drawn_codes`: draws of the given mean and covariance (within 5 standard errors of 20,000 draws),
    the same for the same seed. In `calibrate_by_response` a positive `code_draw_scale` changes the
    network where the codes are fitted on the plan, and nothing where they are given."""
    codes = torch.tensor([[0.5, -1.0], [2.0, 0.0]])
    cov = torch.tensor([[[1.0, 0.6], [0.6, 2.0]], [[0.1, 0.0], [0.0, 0.3]]])
    z = drawn_codes(codes, cov, 4.0, 20_000, seed=3)
    assert z.shape == (20_000, 2, 2) and torch.equal(z, drawn_codes(codes, cov, 4.0, 20_000, seed=3))
    d = z - codes
    assert ((d.mean(0) - 0).abs() < 5 * (4 * torch.diagonal(cov, dim1=-2, dim2=-1) / 20_000).sqrt()).all()
    sample_cov = torch.einsum("nci,ncj->cij", d, d) / len(d)
    torch.testing.assert_close(sample_cov, 4.0 * cov, rtol=5 * (2 / 20_000) ** 0.5 * 2, atol=0.05)

    _, _, fit = made_up
    new, _ = made_up_fleet(1, seed=95)
    X, Y = [new.unit(0).X_train[:40]], [new.unit(0).Y_train[:40]]
    source = source_rows(fit, made_up[0], 50, seed=0)
    probe = new.unit(0).X_val[:30][None]

    def predicted(scale: float, codes: torch.Tensor | None = None) -> torch.Tensor:
        return unit_network_output(fit, source, X, Y, [4.0], replace(FAST_FIT, code_draw_scale=scale), probe,
                                   codes)

    assert not torch.equal(predicted(1.0), predicted(0.0))
    given = fit_codes(fit, X, Y, [4.0], FAST_FIT)
    assert torch.equal(predicted(1.0, given), predicted(0.0, given))


def test_a_saved_recipe_reads_as_it_was_run_and_a_bad_value_is_named():
    old = ResponseRecipe.from_saved({"steps": 10, "code_steps": 300, "code_rows": 1024, "code_lr": 0.03,
                                     "somebody_elses_key": 1})
    assert (old.code_fit, old.inverse_batch, old.steps) == ("adam", 256, 10)  # before the choice existed
    assert old.code_prior == "diagonal" and old.residual_level == "kept"  # saved before entry 131
    assert ResponseRecipe.from_saved(asdict(ResponseRecipe())) == ResponseRecipe()
    for key, value in [("code_fit", "newton"), ("code_prior", "wide"), ("inverse_batch", 0),
                       ("lr", float("nan")), ("steps", "9"), ("code_rows", True), ("residual_ratio", 0.0),
                       ("residual_length", -1.0), ("residual_level", "halved"), ("plan_criterion", "w"),
                       ("inverse_start", "warm"), ("transfer_from", "nowhere")]:
        with pytest.raises(ValueError, match=f"recipe.{key}"):
            ResponseRecipe.from_saved({key: value})


def test_transfer_to_a_training_unit_gives_its_own_rows_back(made_up):
    data, _, fit = made_up
    source = source_rows(fit, data, 50, seed=0)
    own = source.unit == 3
    moved = transfer(fit, source, fit.model.codes.detach()[3])
    torch.testing.assert_close(moved[own], source.X[own], atol=1e-3, rtol=0)
    other = transfer(fit, source, fit.model.codes.detach()[4])
    assert (other[own] - source.X[own]).abs().max() > 10  # another unit reads the same contact otherwise


def test_a_job_trains_as_alone_in_its_group_and_the_joined_fleet_keeps_each_jobs_network(made_up):
    """`calibrate_by_response(groups=...)`: a fleet's epoch is its largest job's, so a small plan
    trained beside a large one takes more steps than alone; in a group of its own each job's network
    is the one it gets alone (what `anytip calibrate` trains), and the joined fleet holds every job's
    network, scalers and id at its own index."""
    _, _, fit = made_up
    new, _ = made_up_fleet(2, seed=97)
    X = [new.unit(0).X_train[:40], new.unit(1).X_train[:400]]
    Y = [new.unit(0).Y_train[:40], new.unit(1).Y_train[:400]]
    source = source_rows(fit, made_up[0], 50, seed=0)
    recipe = replace(FAST_FIT, inverse_batch=64)

    def nets(m: list[int], groups: list[str] | None = None):
        return calibrate_by_response(fit, source, [X[i] for i in m], [Y[i] for i in m], [40.0] * len(m),
                                     MLPConfig(sizes=(C, 16, 5)), recipe, ids=[f"job{i}" for i in m],
                                     groups=groups)[0]

    alone, together, apart = [nets([0]), nets([1])], nets([0, 1]), nets([0, 1], ["small", "large"])
    probe = new.unit(0).X_val[:30][None]
    for m in (0, 1):
        mine = predict(alone[m].model, alone[m].in_scaler, alone[m].out_scaler, probe)[0]
        torch.testing.assert_close(predict(apart.model.model_slice(m), apart.in_scaler.take([m]),
                                           apart.out_scaler.take([m]), probe)[0], mine, rtol=0, atol=0)
    small = predict(together.model.model_slice(0), together.in_scaler.take([0]),
                    together.out_scaler.take([0]), probe)[0]
    assert not torch.equal(small, predict(alone[0].model, alone[0].in_scaler, alone[0].out_scaler, probe)[0])
    assert apart.unit_ids == ["job0", "job1"] and [p["jobs"] for p in apart.extra["parts"]] == [[0], [1]]
    with pytest.raises(ValueError, match="not 0..1 once each"):
        joined_fits([([0], alone[0]), ([0], alone[1])])


def test_no_held_out_units_rows_reach_a_validation_units_network(made_up):
    """`fleet_groups`: a benchmark calibrates its validation (and factor) units in fleets of their
    own, so what they choose is the same whichever units are held out: a validation unit's network
    is bit for bit the same beside a small or a large held-out plan, while one fleet keyed by budget
    alone hands it the held-out unit's epoch length."""
    _, _, fit = made_up
    new, _ = made_up_fleet(3, seed=98)
    X = [new.unit(0).X_train[:40], new.unit(1).X_train[:40], new.unit(2).X_train[:400]]
    Y = [new.unit(0).Y_train[:40], new.unit(1).Y_train[:40], new.unit(2).Y_train[:400]]
    source = source_rows(fit, made_up[0], 50, seed=0)
    recipe, b = replace(FAST_FIT, inverse_batch=64), Budget(40.0, "seconds", "cover")
    probe = new.unit(0).X_val[:30][None]

    def validation_unit(held_out: int, grouped: bool) -> torch.Tensor:
        jobs = [("V", b, None), (f"T{held_out}", b, None)]
        groups = fleet_groups(jobs, [f"T{held_out}"]) if grouped else [b, b]
        assert grouped == (groups[0] != groups[1])
        nets = calibrate_by_response(fit, source, [X[0], X[held_out]], [Y[0], Y[held_out]], [40.0, 40.0],
                                     MLPConfig(sizes=(C, 16, 5)), recipe, ids=["V", "T"], groups=groups)[0]
        return predict(nets.model.model_slice(0), nets.in_scaler.take([0]), nets.out_scaler.take([0]),
                       probe)[0]

    torch.testing.assert_close(validation_unit(1, True), validation_unit(2, True), rtol=0, atol=0)
    assert not torch.equal(validation_unit(1, False), validation_unit(2, False))


def test_a_saved_response_model_loads_equal_and_a_damaged_one_is_named(made_up, tmp_path):
    _, _, fit = made_up
    path = save_response(tmp_path / "response.safetensors", fit.model, fit.noise_var, fit.code_var,
                         {"unit_ids": fit.unit_ids})
    back = load_response(path)
    y = labels(20, torch.Generator().manual_seed(3))
    torch.testing.assert_close(back.model(y, back.model.codes[2]), fit.model(y, fit.model.codes[2]))
    torch.testing.assert_close(back.noise_var, fit.noise_var.cpu())
    assert back.meta["unit_ids"] == fit.unit_ids
    header = json.loads(path.with_suffix(".json").read_text())
    header["n_channels"] = C + 1
    path.with_suffix(".json").write_text(json.dumps(header))
    with pytest.raises(ModelFileError, match="response.safetensors"):
        load_response(path)


RESPONSE = "options.response={code_dim: 4, hidden: 32, layers: 2, steps: 200, code_steps: 50, " \
           "source_rows: 500, rows_per_step: 1024, inverse_epochs: 2}"


@pytest.fixture(scope="module")
def fleet(two_protocol_registry) -> Registry:
    return two_protocol_registry


@pytest.fixture(scope="module")
def response_run(fleet, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("run") / "response"
    return run_experiment(SPEC, fleet, out=out, overrides=[*SECONDS, RESPONSE], progress=False)


def test_the_response_method_scores_held_out_units_on_their_plans(response_run):
    rows = json.loads((response_run / "metrics.json").read_text())["results"]
    prov = json.loads((response_run / "provenance.json").read_text())["cross_sensor"]["seed0"]
    mine = [r for r in rows if r["method"].startswith("response@")]
    assert {r["method"] for r in mine} == {"response@first", "response@spread"}
    assert {r["unit"] for r in mine} == set(prov["units"]["test"])
    for r in mine:
        assert 0 < r["calib_seconds"] <= r["budget_s"] and r["presses"] >= 1
        assert r["force_rmse_n"] > 0 and r["response_residual_pa"] > 0
    assert set(prov["val_loss"]["response@spread"]) == {"8", "40"}
    for method, losses in prov["val_loss"].items():  # each validation unit's loss, whose mean is recorded
        for budget, loss in losses.items():
            units = prov["val_loss_units"][method][budget]
            assert set(units) == set(prov["units"]["val"])
            assert np.mean(list(units.values())) == pytest.approx(loss)
    saved = load_response(response_run / "models" / "response_seed0.safetensors")
    assert saved.meta["unit_ids"] == prov["units"]["train"]  # no validation or held-out unit trains it
    banded = [r for r in mine if "interval_level" in r]  # the spec asks for intervals at level 0.8
    assert banded and all(r["interval_level"] == 0.8 for r in banded)
    assert all(r["interval_rows"] == r["calib_samples"] for r in banded)
    for r in banded:
        assert all(0 <= r[f"{n}_coverage"] <= 1 and r[f"{n}_halfwidth"] > 0 for n in ("fx", "theta"))
        if "fx_fleet_coverage" in r:  # the validation unit's factor, applied
            assert r["fx_fleet_halfwidth"] != r["fx_halfwidth"]
            assert r["interval_test_patches"] >= 1 and 0 <= r["fx_exact_p_outside"] <= 1
            assert r["fx_fleet_coverage_sd"] >= 0
    record = saved.meta["intervals"]
    assert record["level"] == 0.8 and record["residuals"] == "plan"
    assert any(f > 0 for by_budget in record["fleet_factor_by_strategy"].values()
               for factor in by_budget.values() for f in factor.values())
    assert "response@spread" in (response_run / "report.md").read_text()


@pytest.mark.parametrize("design, force_cols, head", [("edge-4baro", 0, "z half-width [m]"),
                                                      ("pad-16baro", 3, "fx half-width [N]")])
def test_the_response_method_runs_on_the_flat_designs(tmp_path, design, force_cols, head):
    """The edge sensor (no force target) and the pad (a force in N beside a position): one orientation,
    no patch grid, plans of whole presses over the design's target space; the report gives each
    output's interval half-width in that output's unit. Each unit's designed calibrations (`plan8`,
    `plan40`, `sensor.flat.design_plan`) are read whole by the benchmark's `designed` strategy (a flat
    design's held-out blocks are spans of its main runs, not places a designed run could press) and by
    `anytip calibrate --plan-strategy designed`."""
    reg = Registry(tmp_path / "flat")
    simulate_flat_into(reg, design, 8, 3, ("short", "plan8", "plan40"))
    over = [o for o in SECONDS if not o.startswith("options.fits")] + [
        RESPONSE, "data.protocol=[short,plan8,plan40]", "options.intervals={folds: 3, level: 0.9}",
        "options.plan_strategies=[spread,designed]"]
    run = run_experiment(SPEC, reg, out=tmp_path / "run", overrides=over, progress=False)
    rows = json.loads((run / "metrics.json").read_text())["results"]
    scored = [r for r in rows if r["method"] == "response@spread" and r["calib_seconds"] > 0]
    assert scored and all(0 < r["calib_seconds"] <= r["budget_s"] and r["presses"] >= 1 for r in scored)
    presses = {b: len(flat.design_plan(flat.get_design(design), b).level) for b in (8, 40)}
    designed = [r for r in rows if r["method"] == "response@designed" and r["calib_seconds"] > 0]
    assert designed and all(r["presses"] == presses[round(r["budget_s"])] for r in designed)
    assert all(r["calib_seconds"] <= r["budget_s"] for r in designed)
    assert load_response(run / "models" / "response_seed0.safetensors").model.force_cols.numel() == force_cols
    report = (run / "report.md").read_text()
    assert head in report and "(N, rad)" not in report
    unit = _held_out(run)
    got = calibrate_unit(run, unit, reg, tmp_path / "unit", budget_seconds=40, method="response",
                         plan_strategy="designed")
    assert any(n.startswith("plan: designed, the unit's plan40 runs") for n in got.notes)
    assert 0 < got.calib_seconds <= 40 and got.check is not None


def _held_out_units(run: Path) -> list[str]:
    return json.loads((run / "provenance.json").read_text())["cross_sensor"]["seed0"]["units"]["test"]


def _held_out(run: Path) -> str:
    return _held_out_units(run)[0]


@pytest.fixture(scope="module")
def designed_fleet(fleet, tmp_path_factory) -> Registry:
    """The fleet with each unit's short and quick runs and its designed calibration of 40 s (`plan40`, what
    `anytip calibrate --plan 40` writes for the rig) simulated after them."""
    from anytip.data.simulated import simulate_into
    from anytip.sensor.fleet import FleetConfig
    from test_cross_sensor import QUICK

    registry = _copied(fleet, tmp_path_factory.mktemp("designed") / "registry")
    simulate_into(registry, FleetConfig(), 8, seed=11, protocols=("short", QUICK, "plan40"))
    return registry


def _copied(registry: Registry, root: Path) -> Registry:
    """A registry at `root` holding a copy of `registry`'s catalog and runs."""
    shutil.copytree(registry.root, root, dirs_exist_ok=True)
    return Registry(root)


def test_calibrate_by_response_writes_the_units_own_network(response_run, fleet, tmp_path, capsys):
    unit = _held_out(response_run)
    assert main(["calibrate", "--model", str(response_run), "--unit", unit, "--budget-seconds", "40",
                 "--method", "response", "--registry", str(fleet.root), "--out", str(tmp_path / "cal")]) == 0
    said = capsys.readouterr().out
    assert "by response transfer" in said and "own check" in said
    assert "validation units at this budget" in said
    saved = load_models(tmp_path / "cal")
    assert saved.meta["method"] == "response" and saved.meta["unit_ids"] == [unit]
    assert tuple(saved.model.config.sizes) == (8, 12, 64, 64, 5)  # the deployed shape: nothing to fold
    record = json.loads((tmp_path / "cal" / "calibration.json").read_text())
    check = record["response_check"]
    assert 0 < check["residual_pa"] and len(check["validation_units_pa"]) == 1
    assert check["alarm"] == (check["over_validation"] > 2.0)
    assert 0 < record["calib_seconds"] <= 40
    assert record["core_gflops"] > 0 and f"{record['core_gflops']:.1f} GFLOP/s" in said  # the time's core
    bands = record["intervals"]  # residuals on the plan's rows, times the validation units' factor
    assert bands["folds"] is None and bands["rows"] == record["calib_samples"] and bands["level"] == 0.9
    assert "intervals from the plan (residuals on its" in said
    assert re.search(r"fx \+-\S+ N, .*theta \+-\S+ rad", said)  # each half-width in its output's unit
    factor = load_response(response_run / "models" / "response_seed0.safetensors").meta["intervals"]
    if factor["level"] != 0.9:  # the benchmark learnt its factor at 0.8: the plan alone, and why
        assert "fleet_factor" not in bands and "learnt at level 0.8" in said


def test_calibrate_caches_the_source_rows_own_responses_and_recomputes_a_bad_one(
        response_run, fleet, tmp_path, monkeypatch):
    """The training units' own responses to the source rows are computed once and cached beside the
    response model: a second calibration reads them and trains the same network bit for bit; a
    cache of another shape is named, computed again and replaced; a cache that cannot be written
    leaves a note and the calibration goes on."""
    import anytip.calibrate.response as calibrate_module

    run = tmp_path / "run"
    shutil.copytree(response_run, run)
    unit, cache = _held_out(run), run / "models" / "response_seed0_source.safetensors"
    cache.unlink(missing_ok=True)
    first = calibrate_unit(run, unit, fleet, tmp_path / "a", budget_seconds=40, method="response")
    assert cache.is_file() and not any("cached" in n or "computed again" in n for n in first.notes)
    made = cache.stat().st_mtime_ns
    calibrate_unit(run, unit, fleet, tmp_path / "b", budget_seconds=40, method="response")
    assert cache.stat().st_mtime_ns == made  # read, not written again
    a, b = load_models(tmp_path / "a"), load_models(tmp_path / "b")
    assert all(torch.equal(x, y) for x, y in zip(a.model.state_dict().values(), b.model.state_dict().values(),
                                                  strict=True))
    from safetensors import safe_open
    from safetensors.torch import save_file
    with safe_open(str(cache), "pt") as f:
        digest = f.metadata()["digest"]
    save_file({"fitted": torch.zeros(3, 8)}, str(cache), {"digest": digest})  # this digest, wrong rows
    bad = calibrate_unit(run, unit, fleet, tmp_path / "c", budget_seconds=40, method="response")
    assert any("_source.safetensors: expected" in n and "computed again" in n for n in bad.notes)
    c = load_models(tmp_path / "c")
    assert all(torch.equal(x, y) for x, y in zip(a.model.state_dict().values(), c.model.state_dict().values(),
                                                  strict=True))
    cache.unlink()

    def refuse(*_: object) -> None:
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(calibrate_module, "save_source_response", refuse)
    kept = calibrate_unit(run, unit, fleet, tmp_path / "d", budget_seconds=40, method="response")
    assert any("could not be cached" in n and "Permission denied" in n for n in kept.notes)
    assert not cache.exists() and load_models(tmp_path / "d").model is not None


def test_calibrate_carries_over_only_the_rows_the_benchmark_trained_on(response_run, fleet, tmp_path):
    """A registry that holds more runs of the training units than the benchmark trained on (a test
    session, a designed calibration) calibrates a new unit as the benchmark's own registry does: those
    runs are no source rows, so the unit's network is the same bit for bit."""
    from anytip.data.simulated import simulate_into
    from anytip.sensor.fleet import FleetConfig
    from test_cross_sensor import QUICK

    unit = _held_out(response_run)
    later = Registry(tmp_path / "later")
    shutil.copytree(fleet.root, later.root, dirs_exist_ok=True)  # the same runs again, and two protocols more
    simulate_into(later, FleetConfig(), 8, seed=11, protocols=("short", QUICK, "retest", "plan40"))
    for run in later.list_runs(unit=unit):  # the new unit keeps its own runs alone
        if run.protocol in ("retest", "plan40"):
            later.remove(run.run_id)
    assert {r.protocol for r in later.list_runs()} > {r.protocol for r in fleet.list_runs()}
    nets = [load_models(calibrate_unit(response_run, unit, reg, tmp_path / name, budget_seconds=40,
                                       method="response", interval_level=None).path)
            for name, reg in (("own", fleet), ("later", later))]
    assert all(torch.equal(x, y) for x, y in zip(*(n.model.state_dict().values() for n in nets), strict=True))


def _set_response_loss(run: Path, value: float) -> None:
    path = run / "models" / "response_seed0.json"
    header = json.loads(path.read_text())
    for strategy in header["meta"]["val_loss_by_strategy"]:  # every plan the response model was scored on
        header["meta"]["val_loss_by_strategy"][strategy] = {"8": value, "40": value}
    path.write_text(json.dumps(header))


def test_calibrate_fits_the_codes_under_the_prior_the_model_records_and_names_a_bad_one(response_run, fleet,
                                                                                       tmp_path):
    """A response model that records `code_prior: registry` calibrates a unit under the prior centred on
    the registry's units it records (`registry_unit_ids`): other codes than the diagonal prior's; a
    prior it does not know, or unit ids that are not a list of ids, are named with the file."""
    unit = _held_out(response_run)
    run = tmp_path / "run"
    shutil.copytree(response_run, run)
    header_path = run / "models" / "response_seed0.json"
    header = json.loads(header_path.read_text())
    assert set(header["meta"]["registry_unit_ids"]) <= set(header["meta"]["unit_ids"])

    def codes_with(prior: object, registry: object, out: str) -> list:
        meta = header["meta"] | {"recipe": header["meta"]["recipe"] | {"code_prior": prior},
                                 "registry_unit_ids": registry}
        header_path.write_text(json.dumps(header | {"meta": meta}))
        calibrate_unit(run, unit, fleet, tmp_path / out, budget_seconds=40, method="response")
        return load_models(tmp_path / out).meta["codes"]

    registry = header["meta"]["registry_unit_ids"]
    diagonal = codes_with("diagonal", registry, "diagonal")
    learnt = codes_with("registry", registry, "registry")
    assert np.abs(np.array(diagonal) - np.array(learnt)).max() > 1e-4
    with pytest.raises(AnytipError, match="recipe.code_prior: 'wide'"):
        codes_with("wide", registry, "wide")
    with pytest.raises(AnytipError, match="registry_unit_ids"):
        codes_with("registry", "U0", "bad")


def test_calibrate_takes_response_transfer_where_its_validation_loss_is_lower(response_run, fleet, tmp_path):
    run = tmp_path / "run"
    shutil.copytree(response_run, run)
    unit = _held_out(run)
    _set_response_loss(run, 1e-9)
    first = calibrate_unit(run, unit, fleet, tmp_path / "a", budget_seconds=40)
    assert first.response_check is not None and any("response transfer" in n for n in first.notes)
    _set_response_loss(run, 1e9)
    second = calibrate_unit(run, unit, fleet, tmp_path / "b", budget_seconds=40)
    assert second.response_check is None and second.own_check is not None  # the folded adapter
    adapter = calibrate_unit(run, unit, fleet, tmp_path / "c", budget_seconds=40, method="adapter")
    assert adapter.response_check is None


def test_calibrate_by_response_names_what_it_lacks(response_run, fleet, tmp_path):
    unit = _held_out(response_run)
    shared = next((response_run / "models").glob("shared_input_affine-film_seed0.safetensors"))
    with pytest.raises(AnytipError, match="needs a cross_sensor run directory"):
        calibrate_unit(shared, unit, fleet, tmp_path / "a", budget_seconds=40, method="response")
    lone = Registry(tmp_path / "lone")  # the new unit's runs only: no training unit to carry over
    lone.add_runs([fleet.open_run(r.run_id) for r in fleet.list_runs(unit=unit)])
    with pytest.raises(AnytipError, match="lacks the response model's training units"):
        calibrate_unit(response_run, unit, lone, tmp_path / "b", budget_seconds=40, method="response")
    with pytest.raises(AnytipError, match="--method must be one of"):
        calibrate_unit(response_run, unit, fleet, tmp_path / "c", budget_seconds=40, method="best")
    with pytest.raises(AnytipError, match="--method response needs labeled presses"):
        calibrate_unit(response_run, unit, fleet, tmp_path / "e", budget_seconds=0, method="response")
    free = calibrate_unit(response_run, unit, fleet, tmp_path / "f", budget_seconds=0)  # auto: label-free
    assert free.response_check is None and any("response transfer needs labels" in n for n in free.notes)
    crafted = tmp_path / "crafted"
    shutil.copytree(response_run, crafted)
    header_path = crafted / "models" / "response_seed0.json"
    header = json.loads(header_path.read_text())
    header["meta"]["recipe"]["inverse_epochs"] = -3
    header_path.write_text(json.dumps(header))
    with pytest.raises(AnytipError, match=r"response_seed0.safetensors: recipe.inverse_epochs: -3"):
        calibrate_unit(crafted, unit, fleet, tmp_path / "d", budget_seconds=40, method="response")


def test_calibrate_reads_a_response_models_record_by_strategy_in_either_layout():
    from anytip.calibrate.records import strategy_table

    new = {"val_loss_by_strategy": {"cover": {"120": 0.05, "600": 0.03}, "spread": {"120": 0.09}}}
    assert strategy_table(new, "val_loss", "cover") == {120.0: 0.05, 600.0: 0.03}
    old = {"val_loss_by_budget": {"120 s cover": 0.05, "120 s spread": 0.09, "30 s cover": 0.2}}
    assert strategy_table(old, "val_loss", "spread") == {120.0: 0.09}
    assert strategy_table(old, "residual", "cover") == {}  # older files recorded no residuals


def test_rescoring_a_run_with_its_own_options_gives_its_rows_back(response_run, fleet, tmp_path):
    """scripts/rescore_response.py reuses the run's response models and references: with the run's
    own options its response rows are the run's, and it refuses what would need a new model."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("rescore", REPO / "scripts" / "rescore_response.py")
    rescore = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(rescore)
    out = tmp_path / "again"
    assert rescore.main([str(response_run), "--registry", str(fleet.root), "--out", str(out)]) == 0
    then = json.loads((response_run / "metrics.json").read_text())["results"]
    now = json.loads((out / "metrics.json").read_text())["results"]
    mine = [r for r in then if r["method"].startswith("response@") or r["method"] == "per_unit"]
    assert now == mine
    assert (out / "models" / "shared_input_affine-film_seed0.safetensors").is_file()  # calibrate reads it
    assert "response@spread" in (out / "report.md").read_text()
    assert f"Rescored by response transfer alone from `{response_run}`;" in (out / "report.md").read_text()
    assert rescore.main([str(response_run), "--registry", str(fleet.root), "--out", str(tmp_path / "b"),
                         "--set", "options.response.hidden=64"]) == 2
    assert not (tmp_path / "b").exists()
    again = tmp_path / "retrained"  # trained again with the run's options: the same model, the same rows
    assert rescore.main([str(response_run), "--registry", str(fleet.root), "--out", str(again),
                         "--retrain"]) == 0
    assert json.loads((again / "metrics.json").read_text())["results"] == mine
    wider = tmp_path / "wider"
    assert rescore.main([str(response_run), "--registry", str(fleet.root), "--out", str(wider), "--retrain",
                         "--set", "options.response.hidden=48"]) == 0
    assert load_response(wider / "models" / "response_seed0.safetensors").model.config.hidden == 48
    assert ("with `--set options.response.hidden=48`, the response models trained again; the source's "
            "description:") in (wider / "report.md").read_text().replace("\n", " ")
    assert len(load_response(again / "models" / "response_seed0.safetensors").meta["training_digest"]) == 64
    crafted = tmp_path / "crafted"
    shutil.copytree(response_run, crafted)
    header_path = crafted / "models" / "response_seed0.json"
    header = json.loads(header_path.read_text())
    header["meta"]["recipe"]["steps"] = "many"
    header_path.write_text(json.dumps(header))
    assert rescore.main([str(crafted), "--registry", str(fleet.root), "--out", str(tmp_path / "c")]) == 2
    assert not (tmp_path / "c").exists()


def test_a_rescoring_on_the_units_simulated_otherwise_is_refused_unless_paired_only(response_run, tmp_path):
    """The run's units and runs simulated again without per-run session conditions: the rescoring
    refuses such a registry, and with --paired-only scores the run's units on it beside the run's
    references, with a report that says the ratios to them mean nothing."""
    import importlib.util

    from anytip.data.simulated import simulate_into
    from anytip.sensor.fleet import FleetConfig, RunConditions
    from test_cross_sensor import QUICK

    spec = importlib.util.spec_from_file_location("rescore", REPO / "scripts" / "rescore_response.py")
    rescore = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(rescore)
    calm = Registry(tmp_path / "calm")
    session = RunConditions(atmosphere_sigma_pa=0, ambient_sigma_c=0, warmup_c=0, wander_c=0, force_bias_n=0)
    simulate_into(calm, FleetConfig(run=session), 8, seed=11, protocols=("short", QUICK))
    command = [str(response_run), "--registry", str(calm.root), "--out"]
    assert rescore.main([*command, str(tmp_path / "a")]) == 2
    out = tmp_path / "paired"
    assert rescore.main([*command, str(out), "--paired-only"]) == 0
    then = json.loads((response_run / "metrics.json").read_text())["results"]
    now = json.loads((out / "metrics.json").read_text())["results"]
    assert [r for r in now if r["method"] == "per_unit"] == [r for r in then if r["method"] == "per_unit"]
    mine = [r for r in then if r["method"].startswith("response@")]
    again = [r for r in now if r["method"].startswith("response@")]
    assert [(r["unit"], r["method"]) for r in again] == [(r["unit"], r["method"]) for r in mine]
    assert all(a["force_rmse_n"] != b["force_rmse_n"] for a, b in zip(again, mine, strict=True))
    assert (out / "report.md").read_text().startswith(f"> {rescore.PAIRED_ONLY_NOTE}")
    assert json.loads((out / "provenance.json").read_text())["paired_only"] is True


def test_a_test_session_moves_the_test_rows_and_the_references_are_scored_again_on_them(response_run, fleet,
                                                                                         tmp_path, capsys):
    """With every unit's test session (`retest`) added, the rescoring tests the held-out units on its rows:
    the run's saved references are scored again there (on the run's own rows they give its rows back),
    and a test session without them is refused, unless the rows are to compare only with each other
    (`--paired-only`: the run's references kept, the rescored methods' rows as with them)."""
    import importlib.util

    from anytip.data.simulated import simulate_into
    from anytip.sensor.fleet import FleetConfig
    from test_cross_sensor import QUICK

    spec = importlib.util.spec_from_file_location("rescore", REPO / "scripts" / "rescore_response.py")
    rescore = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(rescore)
    then = json.loads((response_run / "metrics.json").read_text())["results"]
    base = [str(response_run), "--references", str(response_run / "models"), "--out"]
    same = tmp_path / "same"
    assert rescore.main([*base, str(same), "--registry", str(fleet.root)]) == 0
    kept = [r for r in then if r["method"].startswith("response@") or r["method"] == "per_unit"]
    assert json.loads((same / "metrics.json").read_text())["results"] == kept
    later = Registry(tmp_path / "later")
    shutil.copytree(fleet.root, later.root, dirs_exist_ok=True)
    simulate_into(later, FleetConfig(), 8, seed=11, protocols=("short", QUICK, "retest"))
    command = [str(response_run), "--registry", str(later.root), "--added-protocol", "retest", "--set",
               "data.protocol=[full, short, retest]", "--out"]
    assert rescore.main([*command, str(tmp_path / "none")]) == 2
    out = tmp_path / "retest"
    assert rescore.main([*command, str(out), "--references", str(response_run / "models")]) == 0
    now = json.loads((out / "metrics.json").read_text())["results"]
    for method in ("per_unit", "response@spread"):
        a, b = ([r for r in rows if r["method"] == method] for rows in (then, now))
        assert [r["unit"] for r in a] == [r["unit"] for r in b] and a
        assert all(x["force_rmse_n"] != y["force_rmse_n"] for x, y in zip(a, b, strict=True))
    assert [r.get("reference_lr") for r in then if r["method"] == "per_unit"] == [
        r.get("reference_lr") for r in now if r["method"] == "per_unit"]
    alone = tmp_path / "alone"  # a run that saved no references: the rescored methods compare alone
    assert rescore.main([*command, str(alone), "--paired-only"]) == 0
    rows = json.loads((alone / "metrics.json").read_text())["results"]
    assert [r for r in rows if r["method"] == "per_unit"] == [r for r in then if r["method"] == "per_unit"]
    assert [r for r in rows if r["method"] != "per_unit"] == [r for r in now if r["method"] != "per_unit"]
    assert (alone / "report.md").read_text().startswith(f"> {rescore.PAIRED_ONLY_NOTE}")
    table = _script("fold_table")  # paired with the run, the references as well, only when asked
    with pytest.raises(SystemExit, match="references differ"):
        table.main([str(out), "--against", str(response_run)])
    assert table.main([str(out), "--against", str(response_run), "--test-rows-moved"]) == 0
    said = capsys.readouterr().out
    assert "per_unit -1 s, 2 units: force x" in said and "response@spread 40 s, 2 units" in said


def test_an_interrupted_retraining_resumes_on_the_model_it_saved(response_run, fleet, tmp_path, monkeypatch):
    """A response model is saved as soon as it is trained; the same command on the directory an
    interruption left reuses it where its training digest matches, and trains over a file the
    interruption cut short or one trained another way."""
    import importlib.util

    import anytip.pipelines.cross_sensor_response as method

    spec = importlib.util.spec_from_file_location("rescore", REPO / "scripts" / "rescore_response.py")
    rescore = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(rescore)
    out = tmp_path / "once"
    command = [str(response_run), "--registry", str(fleet.root), "--out", str(out), "--retrain"]
    assert rescore.main(command) == 0
    done = json.loads((out / "metrics.json").read_text())["results"]
    assert rescore.main(command) == 2  # a finished directory is never written over
    (out / "metrics.json").unlink()  # as an interruption after the response model was saved leaves it
    trained = []
    real = method.train_response
    monkeypatch.setattr(method, "train_response", lambda *a, **k: trained.append(1) or real(*a, **k))
    assert rescore.main(command) == 0 and not trained
    assert json.loads((out / "metrics.json").read_text())["results"] == done
    (out / "metrics.json").unlink()
    model = out / "models" / "response_seed0.safetensors"
    model.write_bytes(model.read_bytes()[:100])
    assert rescore.main(command) == 0 and len(trained) == 1
    assert json.loads((out / "metrics.json").read_text())["results"] == done
    (out / "metrics.json").unlink()
    assert rescore.main([*command, "--set", "options.response.steps=300"]) == 0 and len(trained) == 2
    assert load_response(model).meta["recipe"]["steps"] == 300


def test_calibrate_by_response_reads_the_records_of_the_plans_it_makes(response_run, fleet, tmp_path):
    """The response model's records are keyed by plan strategy; calibrate looks them up under the
    strategy its shared model chooses plans by, whatever that is."""
    run = tmp_path / "run"
    shutil.copytree(response_run, run)
    for header_path in (run / "models").glob("shared_*.json"):
        header = json.loads(header_path.read_text())
        header["meta"]["plan_strategy"] = "first"
        header_path.write_text(json.dumps(header))
    path = run / "models" / "response_seed0.json"
    header = json.loads(path.read_text())
    meta = header["meta"]
    for key in ("val_loss_by_strategy", "residual_by_strategy"):
        meta[key] = {"first": meta[key]["spread"]}
    factors = meta["intervals"]["fleet_factor_by_strategy"]
    meta["intervals"]["fleet_factor_by_strategy"] = {"first": factors["spread"]}
    meta["intervals"]["level"] = 0.9
    path.write_text(json.dumps(header))
    got = calibrate_unit(run, _held_out(run), fleet, tmp_path / "cal", budget_seconds=40, method="response")
    assert got.response_check["validation_units_pa"] == meta["residual_by_strategy"]["first"]["40"]
    assert got.intervals["fleet_factor"] == meta["intervals"]["fleet_factor_by_strategy"]["first"]["40"]


def test_calibrate_on_the_units_designed_runs(response_run, designed_fleet, tmp_path, capsys):
    """A new unit whose runs are its designed calibration alone (`plan40`, what `anytip calibrate --plan 40`
    writes for the rig) is calibrated on them as the benchmark's `designed` rows read them: every press of
    those runs in recorded order within the budget, each paying its recorded lead as its move, under the
    response model's record for designed plans (its own check's references, its fleet factor). A model
    without that record says so; a budget of another design, ordinary use where the unit has nothing else
    to read, or a budget in samples are refused by name. With its other runs kept, `--plan-strategy
    designed` reads the same plan, draws ordinary use from the other runs and checks the network on those
    of their rows it did not read."""
    unit = _held_out(response_run)
    both = _copied(designed_fleet, tmp_path / "both")
    alone = _copied(designed_fleet, tmp_path / "alone")
    for run in alone.list_runs(unit=unit):
        if run.protocol != "plan40":
            alone.remove(run.run_id)
    run = tmp_path / "run"
    shutil.copytree(response_run, run)
    path = run / "models" / "response_seed0.json"
    header = json.loads(path.read_text())
    meta = header["meta"]
    for key in ("val_loss_by_strategy", "residual_by_strategy"):
        meta[key]["designed"] = {"40": meta[key]["spread"]["40"]}
    factor = {n: 3.0 for n in meta["output_names"]}
    meta["intervals"] |= {"level": 0.9, "fleet_factor_by_strategy": {"designed": {"40": factor}}}
    path.write_text(json.dumps(header))

    arrays = load_arrays(alone, alone.list_runs(unit=unit))
    stream = calibration_stream(arrays, unit, "plan40")
    presses = find_presses(arrays, unit, stream.outside(arrays))
    expected = select_presses(presses, 40.0, RigTiming(), "first", recorded_moves=True)
    got = calibrate_unit(run, unit, alone, tmp_path / "a", budget_seconds=40, method="response")
    assert any(n.startswith("plan: designed, the unit's plan40 runs") for n in got.notes)
    assert got.calib_samples == len(expected.rows)
    assert got.calib_seconds == pytest.approx(expected.calib_seconds)
    assert got.response_check["validation_units_pa"] == meta["residual_by_strategy"]["designed"]["40"]
    assert got.intervals["fleet_factor"] == factor
    assert got.check is None  # nothing of the unit's is left to check it on

    plain = calibrate_unit(response_run, unit, alone, tmp_path / "b", budget_seconds=40, method="response")
    assert any("scored no designed plans" in n for n in plain.notes) and "fleet_factor" not in plain.intervals
    with pytest.raises(AnytipError, match=r"no runs of the designed calibration of 8 robot-s \(plan8\); "
                                          r"its designed runs: plan40"):
        calibrate_unit(run, unit, alone, tmp_path / "c", budget_seconds=8, method="response")
    with pytest.raises(AnytipError, match=f"unit {unit}: its runs are its designed calibration alone"):
        calibrate_unit(run, unit, alone, tmp_path / "d", budget_seconds=40, use_seconds=60)
    with pytest.raises(AnytipError, match="give --budget-seconds"):
        calibrate_unit(run, unit, alone, tmp_path / "e", budget_samples=100, plan_strategy="designed")
    # a lab's run marked as the design of 1 s whose one press of 2 s does not fit in it
    lab = make_run("LAB-1", n=1000, optional=False)
    lab = replace(lab, in_contact=(lab.time >= 1.0) & (lab.time < 3.0))
    (record,) = alone.add_runs([lab])
    alone.set_protocol(record.run_id, "plan1")
    with pytest.raises(AnytipError, match=r"unit LAB-1: its plan1 runs \(.*\) hold no whole press within 1 "):
        calibrate_unit(run, "LAB-1", alone, tmp_path / "h", budget_seconds=1, method="response")

    kept = calibrate_unit(run, unit, both, tmp_path / "f", budget_seconds=40, method="response",
                          plan_strategy="designed")
    assert (kept.calib_samples, kept.calib_seconds) == (got.calib_samples, got.calib_seconds)
    loaded = load_arrays(both, both.list_runs(unit=unit))  # the rows of its other runs that are read
    others = sum(int((loaded.run == k).sum()) for k, r in enumerate(loaded.runs) if r.protocol != "plan40")
    assert kept.check["rows"] == others > 0
    assert main(["calibrate", "--model", str(run), "--unit", unit, "--budget-seconds", "40", "--registry",
                 str(both.root), "--plan-strategy", "designed", "--out", str(tmp_path / "g")]) == 0
    assert "plan: designed, the unit's plan40 runs" in capsys.readouterr().out


def test_designed_runs_without_in_contact_read_their_presses_from_the_force(response_run, designed_fleet,
                                                                            tmp_path):
    """A lab's designed runs need not hold `in_contact` or `temperature` (both optional in the format):
    their presses are then the contacts their force shows (`force_contact`). Written as a lab writes
    them (the simulator's record dropped, the runs marked `plan40` by hand), the runs hold as many
    presses as with their flag, each within its flagged press (the F/T offset and noise neither add
    contacts nor cut a press in pieces), and the unit's designed plan reads them as `select_presses`
    does within the budget: as many presses as with the flag, each shorter (the flag also holds the
    ramps' lowest rows)."""
    unit = _held_out(response_run)
    flagged = _copied(designed_fleet, tmp_path / "flagged")
    lab = _copied(designed_fleet, tmp_path / "lab")
    for record in lab.list_runs(unit=unit):
        run = lab.open_run(record.run_id)
        lab.remove(record.run_id)
        if record.protocol == "plan40":
            bare = replace(run, in_contact=None, temperature=None,
                           extra={k: v for k, v in run.extra.items() if k != "simulator"})
            (added,) = lab.add_runs([bare])
            lab.set_protocol(added.run_id, "plan40")
    arrays = load_arrays(lab, lab.list_runs(unit=unit))
    assert all(r.protocol == "plan40" for r in arrays.runs)
    presses = find_presses(arrays, unit)
    with_flags = load_arrays(flagged, flagged.list_runs(unit=unit, protocol="plan40"))
    flag_presses = find_presses(with_flags, unit)
    assert len(presses) == len(flag_presses) > 1
    for k in range(len(presses)):
        t, span = arrays.time[presses.rows_of(k)], with_flags.time[flag_presses.rows_of(k)]
        assert presses.run[k] == flag_presses.run[k] and span[0] <= t[0] and t[-1] <= span[-1]
    stream = calibration_stream(arrays, unit, "plan40")
    expected = select_presses(find_presses(arrays, unit, stream.outside(arrays)), 40.0, RigTiming(), "first",
                              recorded_moves=True)

    with_flag = calibrate_unit(response_run, unit, flagged, tmp_path / "a", budget_seconds=40,
                               method="response", plan_strategy="designed")
    bare_got = calibrate_unit(response_run, unit, lab, tmp_path / "b", budget_seconds=40, method="response")
    assert any(n.startswith("plan: designed, the unit's plan40 runs") for n in bare_got.notes)
    assert bare_got.response_check["presses"] == with_flag.response_check["presses"] == expected.presses
    assert bare_got.calib_samples == len(expected.rows) < with_flag.calib_samples
    assert bare_got.calib_seconds == pytest.approx(expected.calib_seconds) and bare_got.calib_seconds <= 40


def test_response_transfer_calibrates_by_the_plans_its_validation_units_scored_best():
    record = {"val_loss_by_strategy": {"spread": {"40": 0.2, "120": 0.1}, "first": {"40": 0.01},
                                       "cover_informative": {"40": 0.1, "120": 0.3}},
              "use_val_loss_by_strategy": {"spread": {"40": 0.05}, "cover_informative": {"40": 0.06}}}
    assert response_strategy(record, "spread", 40) == "cover_informative"
    assert response_strategy(record, "spread", 200) == "spread"  # at 120 s the shared model's is lower
    assert response_strategy(record, "spread", 40, with_use=True) == "spread"
    assert response_strategy(record, "spread", 10) == "spread"  # nothing recorded at or below 10 s
    assert response_strategy(record, "first", 40) == "first"  # lower than every informed selection
    assert response_strategy({}, "first", 40) == "first"
    # an adapter's selection is never swapped for another adapter's, however the response scored it
    assert response_strategy({"val_loss_by_strategy": {"spread": {"40": 0.2}, "first": {"40": 0.1}}},
                             "spread", 40) == "spread"


def test_calibrate_makes_the_plan_the_response_model_chose_with_it(response_run, fleet, tmp_path):
    run = tmp_path / "run"
    shutil.copytree(response_run, run)
    path = run / "models" / "response_seed0.json"
    header = json.loads(path.read_text())
    meta = header["meta"]
    meta["val_loss_by_strategy"]["cover_informative"] = {"8": 1e-9, "40": 1e-9}
    meta["residual_by_strategy"]["cover_informative"] = meta["residual_by_strategy"]["spread"]
    meta["recipe"]["plan_criterion"] = "v"
    path.write_text(json.dumps(header))
    unit = _held_out(run)
    got = calibrate_unit(run, unit, fleet, tmp_path / "cal", budget_seconds=40, method="response")
    assert any(n.startswith("plan: cover_informative") for n in got.notes)
    # the presses select_presses takes with the response model's information under its criterion
    shared = json.loads(next((run / "models").glob("shared_*seed0.json")).read_text())["meta"]
    arrays = load_arrays(fleet, fleet.list_runs(unit=unit))
    stream = calibration_stream(arrays, unit, shared.get("calibration_protocol"))
    presses = find_presses(arrays, unit, stream.outside(arrays))
    rig = RigTiming(**shared["rig"])
    fit = ResponseFit.from_loaded(load_response(run / "models" / "response_seed0.safetensors"))
    information = press_information(fit, arrays, presses, rig.effective_hz, "v")
    plan = select_presses(presses, 40, rig, "cover_informative", int(shared.get("seed", 0)), information)
    assert got.calib_samples == len(plan.rows) and got.calib_seconds == pytest.approx(plan.calib_seconds)
    assert got.calib_seconds <= 40
    assert got.response_check["validation_units_pa"] == meta["residual_by_strategy"]["spread"]["40"]
    meta["recipe"]["plan_criterion"] = "x"
    path.write_text(json.dumps(header))
    with pytest.raises(AnytipError, match="plan_criterion: 'x'"):
        calibrate_unit(run, unit, fleet, tmp_path / "bad", budget_seconds=40, method="response")


def test_calibrate_takes_the_press_selection_asked_for_over_the_runs_choice(response_run, fleet, tmp_path,
                                                                          capsys):
    """A choice made on more validation units than the run's overrides theirs: asked for
    `cover_informative` where the run's units scored it worse, calibrate makes the plan it makes when
    they scored it best; asked for the run's own selection it says so; an unknown selection, a
    designed plan where the unit has no designed runs and an adapter calibration are refused by name."""
    run, chose = tmp_path / "run", tmp_path / "chose"
    shutil.copytree(response_run, run)
    path = run / "models" / "response_seed0.json"
    header = json.loads(path.read_text())
    header["meta"]["recipe"]["plan_criterion"] = "v"
    header["meta"]["val_loss_by_strategy"]["cover_informative"] = {"8": 1e9, "40": 1e9}
    path.write_text(json.dumps(header))
    shutil.copytree(run, chose)
    header["meta"]["val_loss_by_strategy"]["cover_informative"] = {"8": 1e-9, "40": 1e-9}
    (chose / "models" / "response_seed0.json").write_text(json.dumps(header))
    unit = _held_out(run)
    assert main(["calibrate", "--model", str(run), "--unit", unit, "--budget-seconds", "40", "--method",
                 "response", "--plan-strategy", "cover_informative", "--registry", str(fleet.root),
                 "--out", str(tmp_path / "asked")]) == 0
    assert "plan: cover_informative, as asked (--plan-strategy)" in capsys.readouterr().out
    asked = json.loads((tmp_path / "asked" / "calibration.json").read_text())
    best = calibrate_unit(chose, unit, fleet, tmp_path / "best", budget_seconds=40, method="response")
    assert any(n.startswith("plan: cover_informative, the response model's best") for n in best.notes)
    assert (asked["calib_samples"], asked["calib_seconds"]) == (best.calib_samples, best.calib_seconds)
    own = calibrate_unit(run, unit, fleet, tmp_path / "own", budget_seconds=40, method="response",
                         plan_strategy="spread")
    plain = calibrate_unit(run, unit, fleet, tmp_path / "plain", budget_seconds=40, method="response")
    assert "plan: spread, as asked (--plan-strategy)" in own.notes
    assert not any(n.startswith("plan:") for n in plain.notes)

    def weights(name: str) -> torch.Tensor:
        return torch.cat([w.flatten() for w in load_models(tmp_path / name).model.state_dict().values()])

    assert torch.equal(weights("asked"), weights("best")) and torch.equal(weights("own"), weights("plain"))
    assert not torch.equal(weights("asked"), weights("plain"))
    with pytest.raises(AnytipError, match="--plan-strategy 'bogus': expected one of"):
        calibrate_unit(run, unit, fleet, tmp_path / "bogus", budget_seconds=40, method="response",
                       plan_strategy="bogus")
    # a designed plan is the unit's own runs, and this unit has none
    with pytest.raises(AnytipError, match=r"no runs of the designed calibration of 40 robot-s \(plan40\); "
                                          "its designed runs: none"):
        calibrate_unit(run, unit, fleet, tmp_path / "designed", budget_seconds=40, method="response",
                       plan_strategy="designed")
    with pytest.raises(AnytipError, match="--plan-strategy is read by response transfer alone"):
        calibrate_unit(run, unit, fleet, tmp_path / "adapter", budget_seconds=40, method="adapter",
                       plan_strategy="cover")


def test_a_plan_the_spec_decided_is_recorded_reported_and_taken_by_calibrate(response_run, fleet, tmp_path,
                                                                            capsys):
    """`options.response.plan_strategy` decides response transfer's press selection beforehand: the
    response model records it and the report names it; calibrate takes it over the selection the
    run's validation units would give it, exactly as asking for it does. A decision the spec does
    not compare is refused by key, and a recorded one that is no selection by file and key."""
    shared = json.loads(next((response_run / "models").glob("shared_*.json")).read_text())["meta"]
    decided = "spread" if shared["plan_strategy"] == "first" else "first"  # not what calibrate takes today
    rescore, out = _script("rescore_response"), tmp_path / "decided"
    command = [str(response_run), "--registry", str(fleet.root), "--set"]
    assert rescore.main([*command, f"options.response.plan_strategy={decided}", "--out", str(out)]) == 0
    recorded = load_response(out / "models" / "response_seed0.safetensors").meta
    assert recorded["decided_plan_strategy"] == decided
    assert f"(`options.response.plan_strategy`): `{decided}`." in (out / "report.md").read_text()
    undecidable = "options.response.plan_strategy=cover"  # not among the run's plan_strategies
    assert rescore.main([*command, undecidable, "--out", str(tmp_path / "no")]) == 2
    assert "options.response.plan_strategy: 'cover'" in capsys.readouterr().err
    unit = _held_out(out)
    undecided = calibrate_unit(response_run, unit, fleet, tmp_path / "undecided", budget_seconds=40,
                               method="response")
    assert not any(n.startswith("plan:") for n in undecided.notes)  # the shared model's selection
    plain = calibrate_unit(out, unit, fleet, tmp_path / "plain", budget_seconds=40, method="response")
    note = f"plan: {decided}, decided beforehand by the run's spec (options.response.plan_strategy)"
    assert note in plain.notes
    asked = calibrate_unit(out, unit, fleet, tmp_path / "asked", budget_seconds=40, method="response",
                           plan_strategy=decided)
    assert (plain.calib_samples, plain.calib_seconds) == (asked.calib_samples, asked.calib_seconds)
    assert (plain.calib_samples, plain.calib_seconds) != (undecided.calib_samples, undecided.calib_seconds)

    def weights(name: str) -> torch.Tensor:
        return torch.cat([w.flatten() for w in load_models(tmp_path / name).model.state_dict().values()])

    assert torch.equal(weights("plain"), weights("asked"))
    path = out / "models" / "response_seed0.json"
    header = json.loads(path.read_text())
    header["meta"]["decided_plan_strategy"] = "designed"
    path.write_text(json.dumps(header))
    with pytest.raises(AnytipError, match=r"response_seed0\.json: meta\.decided_plan_strategy: 'designed'"):
        calibrate_unit(out, unit, fleet, tmp_path / "bad", budget_seconds=40, method="response")


def _write_lab_run(path: Path, serial: str, k: int, rng) -> None:
    """One run of a made-up 6-barometer pad, written with raw h5py from CALIBRATION_FORMAT.md alone
    (version 2, no in_contact, no temperature, no protocol record): 1 s at rest, then presses at
    random places (u, v in m), each a ramp of normal force with some shear, rest between them."""
    import h5py
    import numpy as np

    rate, place = 100.0, np.array([[-8, -8], [0, -8], [8, -8], [-8, 8], [0, 8], [8, 8]]) * 1e-3
    unit = np.random.default_rng(1000 + k)
    gain, shift = 1 + 0.25 * unit.standard_normal(6), 1e-3 * unit.standard_normal((6, 2))
    force, uv = [np.zeros((100, 3))], [np.zeros((100, 2))]
    for _ in range(30):
        at = rng.uniform(-10e-3, 10e-3, 2)
        ramp = np.sin(np.linspace(0, np.pi, 80)) * rng.uniform(2, 15)
        shear = rng.uniform(-0.3, 0.3, 2)
        f = np.stack([shear[0] * ramp, shear[1] * ramp, -ramp], 1)
        force += [f, np.zeros((20, 3))]
        uv += [np.repeat(at[None], 80, 0), np.repeat(at[None], 20, 0)]
    F, P = np.concatenate(force), np.concatenate(uv)
    d2 = (((P[:, None] - place[None] - shift[None]) / 6e-3) ** 2).sum(-1)
    load = -F[:, 2:3] * (1 + (F[:, None, :2] * (place[None] - P[:, None])).sum(-1) / 2e-2)
    pressure = 101_325 + gain * 900 * load * np.exp(-d2) + 4 * rng.standard_normal((len(F), 6))
    with h5py.File(path, "w") as f:
        f.attrs.update({"format": "calibration_run", "format_version": 2, "sensor_id": serial,
                        "sensor_model": "pad-6baro-lab", "sample_rate_hz": rate, "source": "rig",
                        "created": f"2025-04-{k + 1:02d}T09:00:00Z"})
        f.create_dataset("time", data=np.arange(len(F)) / rate)
        f.create_dataset("pressure", data=pressure.astype(np.float32))
        targets = f.create_group("targets")
        for name, values, unit_name, comps in (("force", F, "N", ["fx", "fy", "fz"]),
                                               ("place", P, "m", ["u", "v"])):
            d = targets.create_dataset(name, data=values.astype(np.float32))
            d.attrs["unit"] = unit_name
            d.attrs["components"] = comps


def _lab_registry(tmp_path: Path) -> Registry:
    """A registry of 9 units' runs written from the format spec alone (`_write_lab_run`)."""
    files = tmp_path / "lab"
    files.mkdir()
    rng = np.random.default_rng(3)
    for u in range(9):
        _write_lab_run(files / f"LAB-P{u}.h5", f"LAB-P{u}", u, rng)
    reg = Registry(tmp_path / "registry")
    reg.import_paths([files])
    return reg


def test_a_budgets_rows_do_not_depend_on_the_other_budgets_and_distil_reads_a_labs_runs(tmp_path):
    """On runs written from the format alone: each budget's networks train apart (entry 79), so a
    run that adds a 40 s budget gives the 20 s rows of a run without it, their plans exactly and their
    scores within float32 rounding; ordinary use
    distilled into the unit's network (`distil: fitted`) scores every held-out unit at both budgets
    and `anytip calibrate` reads it so."""
    reg = _lab_registry(tmp_path)
    over = [o for o in SECONDS if not o.startswith(("options.fits", "options.calibration_protocol"))]
    over += ["options.response={code_dim: 4, hidden: 32, layers: 2, steps: 300, source_rows: 500, "
             "inverse_epochs: 2, inverse_start: pooled, label_free: {seconds: 20, rows: 64, candidates: 256, "
             "rounds: 1, iterations: 2, with_plans: true, zero_shot: false, distil: fitted}}",
             "data.protocol=null", "options.calibration_protocol=null", "options.plan_strategies=[spread]"]
    runs = {b: run_experiment(SPEC, reg, out=tmp_path / f"b{len(b)}", progress=False,
                              overrides=[*over, f"options.budgets=[{','.join(map(str, b))}]"])
            for b in ((0, 20), (0, 20, 40))}
    rows = {b: json.loads((run / "metrics.json").read_text())["results"] for b, run in runs.items()}
    scored = ("_rmse", "_rmse_n", "_halfwidth", "response_residual_pa", "unit", "method", "calib_samples")
    at20 = {b: [{k: v for k, v in r.items() if k.endswith(scored)} for r in got
                if r["method"].startswith("response") and r["budget_s"] == 20] for b, got in rows.items()}
    # errors, widths and plans alike (the coverage diagnostics redraw test patches by the run's job count),
    # each score within float32 rounding: the networks are scored as one batched model of every job, whose
    # kernels may round a row's prediction in its last bit otherwise when the batch holds more networks;
    # a network trained otherwise would move them by orders of magnitude more
    assert len(at20[(0, 20)]) == 4
    for alone, beside in zip(at20[(0, 20)], at20[(0, 20, 40)], strict=True):
        assert alone.keys() == beside.keys()
        assert alone == {k: pytest.approx(v, rel=1e-6) if isinstance(v, float) else v
                         for k, v in beside.items()}
    test = _held_out_units(runs[(0, 20)])
    for budget in (20, 40):
        got = {r["unit"]: r for r in rows[(0, 20, 40)]
               if r["method"] == "response+use+distil@spread" and r["budget_s"] == budget}
        assert set(got) == set(test) and all(np.isfinite(r["u_rmse"]) for r in got.values())
    calibrate_unit(runs[(0, 20)], test[0], reg, tmp_path / "cal", budget_seconds=20, use_seconds=15)
    assert load_models(tmp_path / "cal").meta["method"] == "response+use+distil"


@pytest.mark.parametrize("start", ["scratch", "pooled"])
def test_response_transfer_runs_on_a_registry_written_from_the_format_alone(tmp_path, start):
    """Runs another lab might write (format version 2 from the spec alone: one kind of run per unit,
    no in_contact, temperature or protocol record, its own targets): the response method finds
    the presses, trains on the training units only and calibrates held-out units better than the
    pooled model that ignores how units differ, its networks started from random weights or from
    the pooled start network (there with the recipe spec's registry code prior and plan residual
    correction; from random weights with each transferred row's codes drawn from their posterior)."""
    import numpy as np

    reg = _lab_registry(tmp_path)
    over = [o for o in SECONDS if not o.startswith(("options.fits", "options.calibration_protocol"))]
    # from random weights, each transferred row's codes drawn from their posterior (entry 94's option)
    free = ", code_draw_scale: 1" if start == "scratch" else (
        ", code_prior: registry, residual_length: 1, residual_ratio: 10, "
        "label_free: {seconds: 20, rows: 64, candidates: 256, rounds: 1, "
        "iterations: 2, with_plans: true}")
    # with the pooled start, plans chosen with the response model too (adapters never take them)
    strategies = "[spread]" if start == "scratch" else "[spread, cover_informative]"

    def response(steps: int, rows: int, epochs: int) -> str:
        return (f"options.response={{code_dim: 4, hidden: 32, layers: 2, steps: {steps}, "
                f"source_rows: {rows}, rows_per_step: 1024, inverse_epochs: {epochs}, inverse_start: {start}"
                f"{free}}}")

    over += [response(1500, 2000, 10), "data.protocol=null", "options.calibration_protocol=null",
             "options.budgets=[0,20]", f"options.plan_strategies={strategies}"]
    run = run_experiment(SPEC, reg, out=tmp_path / "run", overrides=over, progress=False)
    rows = json.loads((run / "metrics.json").read_text())["results"]
    prov = json.loads((run / "provenance.json").read_text())["cross_sensor"]["seed0"]["units"]
    mine = {r["unit"]: r for r in rows if r["method"] == "response@spread"}
    pooled = {r["unit"]: r for r in rows if r["method"] == "pooled"}
    assert set(mine) == set(prov["test"]) and all(r["presses"] >= 2 for r in mine.values())
    meta = load_response(run / "models" / "response_seed0.safetensors").meta
    assert meta["unit_ids"] == prov["train"] and meta["recipe"]["inverse_start"] == start
    assert meta["recipe"]["code_prior"] == ("diagonal" if start == "scratch" else "registry")
    assert meta["recipe"]["code_draw_scale"] == (1.0 if start == "scratch" else 0.0)
    assert meta["recipe"]["residual_length"] == (0.0 if start == "scratch" else 1.0)
    assert meta["registry_unit_ids"] == prov["train"]  # the recipe spec's prior, centred on the lab's units
    assert (run / "models" / "response_seed0_start.safetensors").is_file() == (start == "pooled")
    # the place is where units differ most; fz on two held-out units of 20 s plans is within the networks'
    # training noise of the pooled model's (a change of their batch draws alone moves it past it)
    for key in ("u_rmse", "v_rmse"):
        assert np.mean([mine[u][key] for u in mine]) < np.mean([pooled[u][key] for u in mine]), key
    if start == "pooled":  # ordinary use read from such runs: zero-shot and with each plan
        for method in ("response:label_free", "response+use@spread"):
            got = {r["unit"]: r for r in rows if r["method"] == method}
            assert set(got) == set(prov["test"]), method
            assert all(0 < r["unlabeled_seconds"] <= 20 and np.isfinite(r["u_rmse"]) for r in got.values())
        informed = {r["unit"]: r for r in rows if r["method"] == "response@cover_informative"}
        assert set(informed) == set(prov["test"])
        record = json.loads((run / "provenance.json").read_text())["cross_sensor"]["seed0"]
        for method, losses in record["val_loss"].items():  # each validation unit's loss, every method
            for budget, loss in losses.items():
                units = record["val_loss_units"][method][budget]
                assert set(units) == set(prov["val"]) and np.mean(list(units.values())) == pytest.approx(loss)
        assert "How firmly the validation units chose" in (run / "report.md").read_text()
        assert all(0 < r["calib_seconds"] <= 20 and np.isfinite(r["u_rmse"]) for r in informed.values())
        assert not any(r["method"].endswith("@cover_informative") and not r["method"].startswith("response")
                       for r in rows)  # the adapters compare the other plans only
        got = calibrate_unit(run, prov["test"][0], reg, tmp_path / "cal", budget_seconds=20,
                             method="response")
        assert 0 < got.calib_seconds <= 20 and got.response_check is not None
        for budget, method in ((20, "response+use"), (0, "response:label_free")):  # and calibrate does
            cal = calibrate_unit(run, prov["test"][0], reg, tmp_path / f"cal{budget}", budget_seconds=budget,
                                 use_seconds=15)
            assert 0 < cal.unlabeled_seconds <= 15
            assert load_models(tmp_path / f"cal{budget}").meta["method"] == method
    if start == "pooled":  # factor units on such runs: widths of its own targets, and a margin
        more = run_experiment(SPEC, reg, out=tmp_path / "factor", progress=False, overrides=[
            *over, response(500, 1000, 5), "splits.n_train_units=4",  # its intervals are what is read
            "options.intervals={folds: 3, level: 0.8, factor_units: 2}"])
        units = json.loads((more / "provenance.json").read_text())["cross_sensor"]["seed0"]["units"]
        assert len(units["factor"]) == 2
        scored = json.loads((more / "metrics.json").read_text())["results"]
        banded = [r for r in scored if "interval_level" in r]
        assert banded and all(r["u_margin_halfwidth"] >= r["u_fleet_halfwidth"] > 0 and
                              r["u_needed70_halfwidth"] <= r["u_needed85_halfwidth"] for r in banded)
        learnt = load_response(more / "models" / "response_seed0.safetensors").meta["intervals"]
        assert all(set(by) == {*units["val"], *units["factor"]} and all("u" in w["own"] for w in by.values())
                   for by in learnt["units_by_strategy"]["spread"].values())
    if start == "pooled":  # the label-free script reads such a run too, its own targets' ratios
        out = tmp_path / "codes.json"
        assert _script("label_free_codes").main([str(run), "--registry", str(reg.root), "--out", str(out),
                                                 "--rows", "256", "--iterations", "3"]) == 0
        held = [r for r in json.loads(out.read_text())["rows"] if r["role"] == "test"]
        assert held and all(r["place_ratio"] > 0 and r["force_ratio"] > 0 for r in held)


def test_calibrate_pools_the_fleet_factor_with_other_folds_but_never_the_units_own(response_run, fleet,
                                                                                   tmp_path):
    """`--factor-from`: another fold's learners join the run's own in the factor and its margin, except
    the unit calibrated (here recorded as needing 100 times its width, which would dominate the factor);
    a record at another level, a malformed learner, an adapter calibration and a list that holds the
    run's own model alone are refused by name."""
    unit = _held_out(response_run)
    header = json.loads((response_run / "models" / "response_seed0.json").read_text())
    rec = header["meta"]["intervals"]
    own = rec["units_by_strategy"]["spread"]["40"]
    names = tuple(next(iter(own.values()))["own"])

    def scaled(learned: dict, k: float) -> dict:
        return {f: {n: v * (1 if f == "own" else k) for n, v in by_name.items()}
                for f, by_name in learned.items()}

    other = {f"{u}-b": scaled(x, 4.0) for u, x in own.items()}
    other[unit] = scaled(next(iter(own.values())), 100.0)
    rec["units_by_strategy"]["spread"]["40"] = other

    def fold(name: str, record: dict) -> Path:
        (tmp_path / name / "models").mkdir(parents=True)
        shutil.copy(response_run / "models" / "response_seed0.safetensors", tmp_path / name / "models" /
                    "response_seed1.safetensors")
        (tmp_path / name / "models" / "response_seed1.json").write_text(json.dumps(header | {
            "meta": header["meta"] | {"intervals": record}}))
        return tmp_path / name

    b = fold("b", rec)
    got = calibrate_unit(response_run, unit, fleet, tmp_path / "cal", budget_seconds=40, method="response",
                         interval_level=0.8, factor_from=[b])
    learners = [Learner.from_record(x, names) for r in (own, other) for u, x in r.items() if u != unit]
    factor, margin = pooled_factor(learners)
    expected = dict(zip(names, factor * margin.margin, strict=True))
    assert got.intervals["fleet_factor"] == pytest.approx(expected)
    alone = calibrate_unit(response_run, unit, fleet, tmp_path / "alone", budget_seconds=40,
                           method="response", interval_level=0.8)
    assert all(got.intervals["fleet_factor"][n] > alone.intervals["fleet_factor"][n] for n in names)
    with pytest.raises(AnytipError, match="level 0.9, not 0.8"):
        calibrate_unit(response_run, unit, fleet, tmp_path / "c", budget_seconds=40, method="response",
                       interval_level=0.8, factor_from=[fold("c", rec | {"level": 0.9})])
    bad = json.loads(json.dumps(rec))
    next(iter(bad["units_by_strategy"]["spread"]["40"].values()))["needed"][names[0]] = -1
    with pytest.raises(AnytipError, match=f"needed.{names[0]}: -1 is not a finite positive"):
        calibrate_unit(response_run, unit, fleet, tmp_path / "d", budget_seconds=40, method="response",
                       interval_level=0.8, factor_from=[fold("d", bad)])
    with pytest.raises(AnytipError, match="holds no response model"):
        calibrate_unit(response_run, unit, fleet, tmp_path / "e", budget_seconds=40, method="response",
                       factor_from=[tmp_path / "cal"])
    with pytest.raises(AnytipError, match="response transfer alone"):
        calibrate_unit(response_run, unit, fleet, tmp_path / "f", budget_seconds=40, method="adapter",
                       factor_from=[b])
    with pytest.raises(AnytipError, match="nothing to pool"):  # the run itself adds no learner
        calibrate_unit(response_run, unit, fleet, tmp_path / "g", budget_seconds=40, method="response",
                       factor_from=[response_run])


def test_extra_units_train_the_response_model_and_the_registrys_units_carry_over(fleet, tmp_path):
    """With `extra_units` and `transfer_from: registry` the response model learns from the extra
    units too, while a new unit's network is trained on the registry's own training units' rows:
    the model file says which, and `anytip calibrate` needs only those units in the registry."""
    from anytip.data.simulated import simulate_into
    from anytip.sensor.fleet import FleetConfig
    from test_cross_sensor import QUICK

    extra = Registry(tmp_path / "extra")
    simulate_into(extra, FleetConfig(), 3, seed=12, protocols=(QUICK,))
    over = [*SECONDS, RESPONSE.replace("}", ", transfer_from: registry}"),
            "options.adapters=[input_affine+film]", f"options.extra_units={{registry: {extra.root}}}",
            "options.fits=[{}]"]
    run = run_experiment(SPEC, fleet, out=tmp_path / "run", overrides=over, progress=False)
    units = json.loads((run / "provenance.json").read_text())["cross_sensor"]["seed0"]["units"]
    meta = load_response(run / "models" / "response_seed0.safetensors").meta
    assert meta["unit_ids"] == units["train"] + sorted(extra.units())
    assert meta["source_unit_ids"] == units["train"] and meta["recipe"]["transfer_from"] == "registry"
    result = calibrate_unit(run, units["test"][0], fleet, tmp_path / "cal", budget_seconds=40,
                            method="response")
    assert result.response_check is not None and (tmp_path / "cal" / "model.safetensors").is_file()
    # a response model trained elsewhere, on units this machine does not hold: rescoring takes it
    # without reading them, and gives the run's rows back where it is the run's own model
    rescore = _script("rescore_response")
    model = str(run / "models" / "response_seed{seed}.safetensors")
    shutil.rmtree(extra.root)
    out = tmp_path / "elsewhere"
    assert rescore.main([str(run), "--registry", str(fleet.root), "--out", str(out), "--response-model",
                         model]) == 0
    mine = [r for r in json.loads((run / "metrics.json").read_text())["results"]
            if r["method"].startswith("response@") or r["method"] == "per_unit"]
    assert json.loads((out / "metrics.json").read_text())["results"] == mine
    crafted = tmp_path / "crafted"  # a model that learnt a held-out unit is refused
    shutil.copytree(run / "models", crafted)
    header = json.loads((crafted / "response_seed0.json").read_text())
    header["meta"]["unit_ids"][-1] = units["test"][0]
    (crafted / "response_seed0.json").write_text(json.dumps(header))
    assert rescore.main([str(run), "--registry", str(fleet.root), "--out", str(tmp_path / "leak"),
                         "--response-model", str(crafted / "response_seed{seed}.safetensors")]) == 2
    assert rescore.main([str(run), "--registry", str(fleet.root), "--out", str(tmp_path / "all"),
                         "--response-model", model, "--set", "options.response.transfer_from=all"]) == 2
    assert not (tmp_path / "leak").exists() and not (tmp_path / "all").exists()


def test_response_models_of_many_simulated_units_take_the_registrys_rows_and_rescore(tmp_path, monkeypatch,
                                                                                   capsys):
    """scripts/response_many_units.py simulates a run's training units again (from their fleet seed)
    and more units beside them, in worker processes through registries of their own: the training
    units' rows equal the pipeline's bit for bit, its models learn them and the extra units, and
    rescoring takes such a model without the extra units on this machine."""
    from anytip.config import load_spec
    from anytip.data.simulated import simulate_into
    from anytip.pipelines.common import Context, load
    from anytip.pipelines.cross_sensor import min_units, prepare
    from anytip.pipelines.cross_sensor_options import parse_options
    from anytip.sensor.fleet import FleetConfig

    registry = Registry(tmp_path / "reg")
    simulate_into(registry, FleetConfig(), 8, seed=21, protocols=("short",))
    over = [*SECONDS, RESPONSE.replace("}", ", transfer_from: registry}"), "options.fits=[{}]",
            "options.adapters=[]", "options.plan_strategies=[spread]"]
    run = run_experiment(SPEC, registry, out=tmp_path / "run", overrides=over, progress=False)
    monkeypatch.syspath_prepend(str(REPO / "scripts"))  # its worker processes import it by name
    many = importlib.import_module("response_many_units")
    out = tmp_path / "many"
    assert many.main([str(run), "--registry-seed", "21", "--registry-protocols", "short", "--extra-seed",
                      "22", "--extra", "2", "--extra-protocols", "short", "--workers", "2", "--device", "cpu",
                      "--steps", "30", "--max-rows", "300", "--out", str(out)]) == 0
    # the calls below fork their workers: the script's spawned ones (safe beside CUDA) are checked above,
    # and each spawn imports torch anew
    monkeypatch.setattr(many, "get_context", lambda method: multiprocessing.get_context("fork"))
    digests = json.loads(next(out.glob("log_*.json")).read_text())["registry_rows_sha256"]["run_seed0"]
    spec = load_spec(run / "config.yaml", ["options.adapters=[]"])
    ctx = Context(spec, registry, tmp_path / "x", torch.device("cpu"), False, {})
    sd = prepare(ctx, load(ctx, min_units(ctx)), parse_options(ctx), 0)
    for k in range(sd.train.n_units):
        r = sd.train.unit(k)
        rows = (r.unit_id, *(t.numpy() for t in (r.X_train, r.Y_train, r.X_val, r.Y_val)))
        assert many.rows_digest(rows) == digests[r.unit_id]
    check = _script("response_rows_check")  # the same comparison as a command
    log = next(out.glob("log_*.json"))
    assert check.main([str(run), "--registry", str(registry.root), "--log", str(log)]) == 0
    (tmp_path / "none.json").write_text(json.dumps({"registry_rows_sha256": {}}))  # nothing to compare
    assert check.main([str(run), "--registry", str(registry.root), "--log", str(tmp_path / "none.json")]) == 1
    model = out / "run_seed0_extra2_rps1024.safetensors"
    assert load_response(model).meta["unit_ids"] == [*sd.train.unit_ids, "SIM22-000", "SIM22-001"]
    # --extra-store: the first call keeps the extra units' registries, the next reads them back;
    # both give the model of a fresh simulation byte for byte, and a store without a unit is named
    common = [str(run), "--registry-seed", "21", "--registry-protocols", "short", "--extra-seed", "22",
              "--extra-protocols", "short", "--workers", "2", "--device", "cpu", "--steps", "30",
              "--max-rows", "300", "--extra-store", str(tmp_path / "store")]
    for again, split in (("kept", []), ("read", ["--extra-split-seed", "0"])):  # seed 0: the run's own
        assert many.main([*common, "--extra", "2", *split, "--out", str(tmp_path / again)]) == 0
        assert (tmp_path / again / model.name).read_bytes() == model.read_bytes()
    assert many.main([*common, "--extra", "2", "--extra-split-seed", "5", "--out", str(tmp_path / "s5")]) == 0
    assert (tmp_path / "s5" / model.name).read_bytes() != model.read_bytes()  # other extra rows
    capsys.readouterr()
    assert many.main([*common, "--extra", "3", "--out", str(tmp_path / "more")]) == 2
    assert "stored extra units lack ['SIM22-002']" in capsys.readouterr().err
    rescore = _script("rescore_response")
    again = tmp_path / "rescored"
    assert rescore.main([str(run), "--registry", str(registry.root), "--out", str(again), "--response-model",
                         str(model), "--set", "options.response.steps=30"]) == 0
    rows = [r for r in json.loads((again / "metrics.json").read_text())["results"]
            if r["method"].startswith("response@")]
    assert rows and all(r["n_extra_units"] == 2 for r in rows)
    assert rescore.main([str(run), "--registry", str(registry.root), "--out", str(tmp_path / "other"),
                         "--response-model", str(model)]) == 2  # trained with other steps than the spec's


def test_every_new_unit_starts_from_the_pooled_network_the_run_saved(fleet, tmp_path):
    """`inverse_start: pooled`: the run trains one network on the source rows as measured and
    saves it beside the response model; the benchmark and `anytip calibrate` start each new
    unit's network from it (its scalers too), and calibrate names the file when it is missing
    or of another shape."""
    from anytip.models.io import save_models
    from anytip.models.mlp import BatchedMLP, MLPConfig
    from anytip.models.scaler import Scaler

    over = [*SECONDS, RESPONSE.replace("}", ", inverse_start: pooled, inverse_lr: 0.003}"),
            "options.adapters=[input_affine+film]", "options.fits=[{}]"]
    run = run_experiment(SPEC, fleet, out=tmp_path / "run", overrides=over, progress=False)
    rows = json.loads((run / "metrics.json").read_text())["results"]
    assert any(r["method"] == "response@spread" for r in rows)
    start_file = run / "models" / "response_seed0_start.safetensors"
    start = load_models(start_file)
    assert start.meta["unit_ids"] == ["pooled"] and start.model.n_models == 1
    recipe = load_response(run / "models" / "response_seed0.safetensors").meta["recipe"]
    assert recipe["inverse_start"] == "pooled" and recipe["inverse_lr"] == 0.003
    unit = _held_out(run)
    calibrate_unit(run, unit, fleet, tmp_path / "cal", budget_seconds=40, method="response")
    mine = load_models(tmp_path / "cal")
    assert torch.equal(mine.in_scaler.mean, start.in_scaler.mean)
    assert torch.equal(mine.out_scaler.std, start.out_scaler.std)
    save_models(start_file, BatchedMLP(1, MLPConfig(sizes=(8, 16, 5))), Scaler.identity(1, 8),
                Scaler.identity(1, 5), {})
    with pytest.raises(AnytipError, match="response_seed0_start.safetensors: 1 network"):
        calibrate_unit(run, unit, fleet, tmp_path / "b", budget_seconds=40, method="response")
    start_file.unlink()
    with pytest.raises(AnytipError, match="response_seed0_start"):
        calibrate_unit(run, unit, fleet, tmp_path / "c", budget_seconds=40, method="response")


def test_response_many_units_names_its_models_as_extra_units_and_rows_per_step():
    """--models EXTRA:ROWS_PER_STEP lists each model; without it, the recipe's rows per step at each
    count of --extra and --rows-per-step's at the largest; a malformed list is refused by name."""
    many = _script("response_many_units")
    args = argparse.Namespace(models="128:32768,1024:32768,128:4096", extra="128,1024", rows_per_step="")
    assert many.models_of(args, 4096) == {128: [32768, 4096], 1024: [32768]}
    args = argparse.Namespace(models="", extra="128,1024", rows_per_step="32768")
    assert many.models_of(args, 4096) == {128: [4096], 1024: [4096, 32768]}
    for bad in ("128", "128:x", "128:1:2", "-1:4096"):
        with pytest.raises(AnytipError, match="--models"):
            many.models_of(argparse.Namespace(models=bad, extra="", rows_per_step=""), 4096)


def _script(name: str):
    """A script of scripts/ as a module."""
    import importlib.util
    import sys

    spec = importlib.util.spec_from_file_location(name, REPO / "scripts" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def test_transfer_bounds_scores_every_arm_and_fold_table_every_run(response_run, fleet, tmp_path, capsys):
    """scripts/transfer_bounds.py: a row per unit and arm; arms that know the new unit alike give it
    the same test-patch residual. scripts/fold_table.py: one table over runs, and a unit held out
    in two runs is refused, and a run against itself is paired at 1. scripts/response_model_table.py:
    a table of such rows, and pairs."""
    bounds = _script("transfer_bounds")
    out = tmp_path / "bounds.json"
    assert bounds.main([str(response_run), "--registry", str(fleet.root), "--budget", "40",
                        "--out", str(out)]) == 0
    rows = json.loads(out.read_text())["rows"]
    units = {r["unit"] for r in rows}
    assert {(r["unit"], r["arm"]) for r in rows} == {(u, a) for u in units for a in bounds.ARMS}
    by = {(r["unit"], r["arm"]): r for r in rows}
    for u in units:
        assert by[u, "plan"]["test_residual_pa"] == by[u, "source"]["test_residual_pa"] > 0
        assert by[u, "oracle"]["test_residual_pa"] == by[u, "both"]["test_residual_pa"] > 0
    held = [r for r in rows if r["role"] == "test"]
    assert held and all(r["force_ratio"] > 0 and r["angle_ratio"] > 0 for r in held)
    assert all(r["val_loss_mean"] > 0 for r in rows if r["role"] == "val")

    table = _script("fold_table")
    assert table.main([str(response_run)]) == 0
    assert "| response@spread | 40 |" in capsys.readouterr().out
    with pytest.raises(SystemExit, match="is held out in"):
        table.main([str(response_run), str(response_run)])
    assert table.main([str(response_run), "--against", str(response_run)]) == 0  # a run against itself
    said = capsys.readouterr().out
    assert "response@spread 40 s" in said and "force x1.000 [1.000, 1.000]" in said

    models = _script("response_model_table")  # a model's rows against themselves: every paired ratio is 1
    assert models.main([str(out), "--pair", "bounds:bounds", "--pooled"]) == 0
    printed = capsys.readouterr().out
    assert "| bounds | oracle |" in printed and "force_ratio 1.000 [1.000, 1.000]" in printed
    pooled = {ln.split("|")[2].strip(): ln for ln in printed.splitlines() if ln.startswith("| all |")}
    by_file = {ln.split("|")[2].strip(): ln for ln in printed.splitlines() if ln.startswith("| bounds |")}
    assert pooled and {a: ln.split("|")[3:] for a, ln in pooled.items()} == \
        {a: ln.split("|")[3:] for a, ln in by_file.items()}  # one file: pooled over it is the file


def test_fold_table_ceiling_reads_the_rows_needed_halfwidths_at_their_level(capsys):
    """scripts/fold_table.py --ceiling: the band and floor come from the rows' interval level, and
    one factor per output is judged by the half-widths each row's test rows needed."""
    table = _script("fold_table")
    rows = []
    for k, need in enumerate((1.0, 1.1, 2.0)):  # unit k's test rows need `need` times its own width
        rows.append({"method": "m@cover", "budget_s": 120, "unit": f"U{k}", "interval_level": 0.8,
                     "x_halfwidth": 1.0, "x_fleet_halfwidth": 1.1, "x_fleet_coverage": 0.8,
                     **{f"x_needed{c}_halfwidth": need * f for c, f in ((70, 0.9), (75, 0.95), (85, 1.1))}})
    said = table.ceilings(rows)
    # level 0.8: floor 0.70, band [0.75, 0.85]; as factors the bands are [0.95, 1.1], [1.045, 1.21] and
    # [1.9, 2.2]: 1.045 puts two in; above every floor (1.8) only the third's band is reached, at 1.9
    assert "3 units: one factor per output puts at most 67% in the band, 33% with none below 0.70 (x 1.90)" \
        in said
    assert table.edges_of(rows) == pytest.approx((0.7, 0.75, 0.85))
    with pytest.raises(SystemExit, match="several levels"):
        table.edges_of([*rows, {**rows[0], "interval_level": 0.9}])


def _fold_run(root: Path, seed: int, held: dict[str, tuple[float, float]],
              learners: dict[str, float]) -> Path:
    """A finished fold made from the row and model-record format alone: one output `x` at level 0.9;
    each held-out unit's row with its own half-width 1, the factor its fold's learners give and the
    half-widths its test rows needed (0.80, 0.85, 0.95 at `held[u]`'s (low, high) times 0.9, 1, 1);
    each learner with own half-width 1 and needed `learners[u]`."""
    run = root / f"fold{seed}"
    (run / "models").mkdir(parents=True)
    factor = float(np.exp(np.mean(np.log(list(learners.values())))))
    rows = []
    for u, (low, high) in held.items():
        errors = {"force_rmse_n": 1.0, "angle_rmse_rad": 0.1}
        rows.append({"method": "per_unit", "unit": u, "seed": seed, **errors})
        rows.append({"method": "response+use@cover", "unit": u, "seed": seed, "budget_s": 120, **errors,
                     "interval_level": 0.9, "x_halfwidth": 1.0, "x_fleet_halfwidth": factor,
                     "x_needed80_halfwidth": 0.9 * low, "x_needed85_halfwidth": low,
                     "x_needed95_halfwidth": high})
    (run / "metrics.json").write_text(json.dumps({"results": rows}))
    record = {u: {"own": {"x": 1.0}, "needed": {"x": n}, "at_floor": {"x": n}, "at_low": {"x": n},
                  "at_high": {"x": n}} for u, n in learners.items()}
    meta = {"intervals": {"level": 0.9, "use_units_by_strategy": {"cover": {"120": record}}}}
    (run / "models" / f"response_seed{seed}.json").write_text(json.dumps({"meta": meta}))
    (run / "models" / f"response_seed{seed}_start.json").write_text(json.dumps({"meta": {}}))
    for stem in (f"response_seed{seed}", f"response_seed{seed}_start"):  # the weights, never read here
        (run / "models" / f"{stem}.safetensors").write_bytes(b"")
    return run


def test_fold_table_pooled_learns_each_folds_factor_from_every_fold_but_its_held_out_units(tmp_path, capsys):
    """scripts/fold_table.py --pooled: fold 0 learns from L1 and L2 but not from A1, which it holds out
    (factor sqrt(2), two learners, no margin: A1 lands in its band); fold 1 from L1, L2 and A1 (factor
    2.52, at most 1.2 times that with its margin: B1 needs 3.15 to reach the floor, so it falls below)."""
    table = _script("fold_table")
    a = _fold_run(tmp_path, 0, {"A1": (1.3, 1.5)}, {"L1": 2.0})
    b = _fold_run(tmp_path, 1, {"B1": (3.5, 4.0)}, {"L2": 1.0, "A1": 8.0})
    said = table.pooled([a, b])
    assert ("response+use@cover 120 s, pooled factor x margin: 50% of 2 unit-outputs in [0.85, 0.95], "
            "1 below 0.80") in said
    assert f"{a} seed 0: 2 learners, margin 1, factor x 1.41" in said
    assert f"{b} seed 1: 3 learners" in said and "factor x 2.52" in said
    drift = float(said.split("rows' factor to ")[1].split()[0])
    assert drift < 1e-12  # each fold's own learners give the factor its rows used
    assert table.main([str(a), str(b), "--pooled"]) == 0
    assert "50% of 2 unit-outputs" in capsys.readouterr().out


def test_label_free_codes_scores_every_arm_and_never_raises_its_objective(fleet, tmp_path):
    """scripts/label_free_codes.py on a run with a pooled start: a row per unit and arm, and the joint
    fits, from codes zero, from the truth and from the contact search, only keep steps that lower
    their objective."""
    over = [*SECONDS, RESPONSE.replace("}", ", inverse_start: pooled}"), "options.adapters=[]"]
    run = run_experiment(SPEC, fleet, out=tmp_path / "run", overrides=over, progress=False)
    script = _script("label_free_codes")
    out = tmp_path / "codes.json"
    assert script.main([str(run), "--registry", str(fleet.root), "--out", str(out),
                        "--rows", "256", "--iterations", "4", "--plan-seconds", "40"]) == 0
    rows = json.loads(out.read_text())["rows"]
    units = {r["unit"] for r in rows}
    arms = [a for a in script.ARMS if a != "encoder_more"]  # that one needs --encoder-units
    assert {(r["unit"], r["arm"]) for r in rows} == {(u, a) for u in units for a in arms}
    for r in rows:
        assert r["unlabeled_rows"] <= 256 and r["force_rmse_n"] > 0
        for trace in (r["objective"], r["objective_joint_truth"], r["objective_joint_search"],
                      r["objective_joint_scale"], r["objective_joint_scale_start"],
                      r["objective_joint_scale_encoder"]):
            assert all(b <= a for a, b in zip(trace, trace[1:], strict=False))
        assert r["objective_joint_truth"][0] <= r["objective_at_truth"]  # started at the truth: never above
    by = {(r["unit"], r["arm"]): r for r in rows}
    for u in units:
        assert by[u, "zero"]["test_residual_pa"] > 0 and "test_residual_pa" not in by[u, "pooled"]
    held = [r for r in rows if r["role"] == "test"]
    assert held and all(r["force_ratio"] > 0 for r in held)


def test_the_label_free_zero_shot_row_scores_every_held_out_unit_from_its_ordinary_use(fleet, tmp_path):
    """options.response.label_free: a `response:label_free` row per held-out unit at no labeled
    budget and no rig time, its unlabeled contact seconds within the option's, a validation loss
    the report chooses the zero-shot method on; refused without the pooled start it pulls towards."""
    free = "label_free: {seconds: 20, rows: 64, candidates: 256, rounds: 1, iterations: 2, with_plans: true}"
    over = [*SECONDS, RESPONSE.replace("}", f", inverse_start: pooled, {free}}}"),
            "options.adapters=[input_affine]", "options.fits=[{}]"]  # calibrate needs a shared model
    run = run_experiment(SPEC, fleet, out=tmp_path / "run", overrides=over, progress=False)
    rows = json.loads((run / "metrics.json").read_text())["results"]
    prov = json.loads((run / "provenance.json").read_text())["cross_sensor"]["seed0"]
    mine = [r for r in rows if r["method"] == "response:label_free"]
    assert {r["unit"] for r in mine} == set(prov["units"]["test"])
    for r in mine:
        assert r["calib_samples"] == 0 and r["calib_seconds"] == 0 and r["budget_s"] == 0
        assert 0 < r["unlabeled_seconds"] <= 20 and r["unlabeled_samples"] > 0 and r["force_rmse_n"] > 0
    assert set(prov["val_loss"]["response:label_free"]) == {"0"}
    assert "response:label_free" in (run / "report.md").read_text()
    # with_plans: every labeled row again, its codes from the plan and the unit's ordinary use together
    def keyed(method: str) -> dict[tuple, dict]:
        return {(r["unit"], r["method"], r["budget_s"]): r for r in rows if r["method"].startswith(method)}

    plain = {(u, m.replace("response@", ""), b): r for (u, m, b), r in keyed("response@").items()}
    joint = {(u, m.replace("response+use@", ""), b): r for (u, m, b), r in keyed("response+use@").items()}
    assert joint.keys() == plain.keys() and joint
    for key, r in joint.items():
        assert r["calib_seconds"] == plain[key]["calib_seconds"] and r["presses"] == plain[key]["presses"]
        assert 0 < r["unlabeled_seconds"] <= 20 and r["force_rmse_n"] > 0
        assert r["interval_level"] == plain[key]["interval_level"] == 0.8  # intervals as response@'s
        assert r["interval_rows"] == plain[key]["interval_rows"]
    assert any(r["force_rmse_n"] != plain[key]["force_rmse_n"] for key, r in joint.items())  # other codes
    assert set(prov["val_loss"]["response+use@spread"]) == set(prov["val_loss"]["response@spread"])
    # zero_shot: false scores the same labeled rows with ordinary use, without the zero-shot row
    use_free = free.replace("}", ", zero_shot: false}")
    alone = [*SECONDS, RESPONSE.replace("}", f", inverse_start: pooled, {use_free}}}"), "options.adapters=[]"]
    use_only = run_experiment(SPEC, fleet, out=tmp_path / "use_only", overrides=alone, progress=False)
    again = json.loads((use_only / "metrics.json").read_text())["results"]
    assert not any(r["method"] == "response:label_free" for r in again)
    assert {k: r["force_rmse_n"] for k, r in joint.items()} == {
        (r["unit"], r["method"].replace("response+use@", ""), r["budget_s"]): r["force_rmse_n"]
        for r in again if r["method"].startswith("response+use@")}
    bad = [*SECONDS, RESPONSE.replace("}", f", {free}}}")]
    with pytest.raises(AnytipError, match="label_free needs inverse_start: pooled"):
        run_experiment(SPEC, fleet, out=tmp_path / "bad", overrides=bad, progress=False)
    _calibrate_with_ordinary_use(run, fleet, tmp_path)


def _calibrate_with_ordinary_use(run: Path, fleet: Registry, tmp_path: Path) -> None:
    """`anytip calibrate --ordinary-use`: the run's response model records how its benchmark read
    ordinary use; a unit calibrated with its plan and ordinary use gets other codes than from the plan
    alone, with the unlabeled seconds asked for; at budget 0 from the ordinary use alone; the adapter,
    too many seconds and a crafted record are refused, naming what is wrong."""
    unit = _held_out(run)
    response = run / "models" / "response_seed0.safetensors"
    saved = load_response(response).meta
    assert saved["label_free"]["recipe"]["seconds"] == 20 and saved["use_val_loss_by_strategy"]["spread"]
    assert saved["intervals"]["use_fleet_factor_by_strategy"]["spread"]
    header = json.loads(response.with_suffix(".json").read_text())
    header["meta"]["label_free"]["recipe"]["iterations"] = 30  # the run's 2 steps leave a 40 s plan's codes
    response.with_suffix(".json").write_text(json.dumps(header))
    plain = calibrate_unit(run, unit, fleet, tmp_path / "plain", budget_seconds=40, method="response")
    both = calibrate_unit(run, unit, fleet, tmp_path / "both", budget_seconds=40, use_seconds=15)
    assert both.calib_seconds == plain.calib_seconds and 0 < both.unlabeled_seconds <= 15
    codes = {k: load_models(tmp_path / k).meta for k in ("plain", "both")}
    assert codes["both"]["method"] == "response+use" and codes["plain"]["method"] == "response"
    assert codes["both"]["codes"] != codes["plain"]["codes"]
    assert both.intervals is not None and not any("no fleet factor" in n for n in both.notes)
    # at the benchmark's level: 15 s of use weighs less than the 20 s its use factor was learnt on, so the
    # intervals take the plan alone's factor, as without use; 20 s take the use factor
    at = {s: calibrate_unit(run, unit, fleet, tmp_path / f"level_{s}", budget_seconds=40, use_seconds=s,
                            interval_level=0.8, method="response") for s in (0, 15, 20)}
    assert at[15].intervals["fleet_factor"] == at[0].intervals["fleet_factor"]
    said = "intervals: the plan alone's fleet factor, as the ordinary use read weighs 15.0 s, less than"
    assert any(n.startswith(said) and " the 20 s " in n for n in at[15].notes)
    assert at[20].intervals["fleet_factor"] != at[0].intervals["fleet_factor"]
    assert not any("the plan alone's fleet factor" in n for n in at[20].notes + at[0].notes)
    alone = calibrate_unit(run, unit, fleet, tmp_path / "alone", budget_seconds=0, use_seconds=600)
    assert alone.calib_samples == 0 and 0 < alone.unlabeled_seconds < 600
    said = f"{alone.unlabeled_seconds:.1f} s of contact read of the 600 s asked (all the stream holds)"
    assert said in " ".join(alone.notes)
    assert load_models(tmp_path / "alone").meta["method"] == "response:label_free"
    assert main(["calibrate", "--model", str(run), "--unit", unit, "--budget-seconds", "0", "--ordinary-use",
                 "15", "--registry", str(fleet.root), "--out", str(tmp_path / "cli")]) == 0
    with pytest.raises(AnytipError, match="--ordinary-use is read by response transfer alone"):
        calibrate_unit(run, unit, fleet, tmp_path / "a", budget_seconds=40, method="adapter", use_seconds=15)
    with pytest.raises(AnytipError, match=r"--ordinary-use must lie in \[0, 600\]"):
        calibrate_unit(run, unit, fleet, tmp_path / "b", budget_seconds=40, use_seconds=601)
    _designed_plan_with_ordinary_use(run, fleet, unit, tmp_path)
    _calibrate_with_a_use_log(run, fleet, unit, tmp_path)
    header["meta"]["label_free"]["recipe"]["rows"] = 0
    response.with_suffix(".json").write_text(json.dumps(header))
    with pytest.raises(AnytipError, match=r"response_seed0.json: meta.label_free: recipe: rows"):
        calibrate_unit(run, unit, fleet, tmp_path / "c", budget_seconds=40, use_seconds=15)
    del header["meta"]["label_free"]  # benchmarked without the option: the defaults, said so
    response.with_suffix(".json").write_text(json.dumps(header))
    old = calibrate_unit(run, unit, fleet, tmp_path / "d", budget_seconds=40, use_seconds=15)
    assert any("records no ordinary-use reading" in n for n in old.notes) and old.unlabeled_samples > 0


def _designed_plan_with_ordinary_use(run: Path, fleet: Registry, unit: str, tmp_path: Path) -> None:
    """`--plan-strategy designed --ordinary-use`: the plan from the unit's designed runs, its ordinary use
    drawn from its other runs, and the network checked on the rows of those runs it did not read."""
    from anytip.data.simulated import simulate_into
    from anytip.sensor.fleet import FleetConfig
    from test_cross_sensor import QUICK

    both = Registry(tmp_path / "designed_registry")
    shutil.copytree(fleet.root, both.root, dirs_exist_ok=True)
    simulate_into(both, FleetConfig(), 8, seed=11, protocols=("short", QUICK, "plan40"))
    got = calibrate_unit(run, unit, both, tmp_path / "designed", budget_seconds=40, use_seconds=15,
                         plan_strategy="designed")
    loaded = load_arrays(both, both.list_runs(unit=unit))
    designed = [k for k, r in enumerate(loaded.runs) if r.protocol == "plan40"]
    assert got.calib_samples == int(np.isin(loaded.run, designed).sum())  # the whole design within 40 s
    assert 0 < got.unlabeled_seconds <= 15 and got.unlabeled_samples > 0
    assert got.check["rows"] == int((~np.isin(loaded.run, designed)).sum()) - got.unlabeled_samples
    # whole presses stop short of the 15 s asked where the stream holds more: routine, no note
    assert not any(n.startswith("ordinary use:") for n in got.notes)


def _calibrate_with_a_use_log(run: Path, fleet: Registry, unit: str, tmp_path: Path) -> None:
    """`--use-log`: a log of the unit's pressures alone (here its short runs' pressures), its contacts found
    from them, read as its ordinary use instead of its runs; a log of another unit, a log without
    `--ordinary-use` and a log with no contact are refused by name."""
    from anytip.data.use_log import UseLog, write_use_log

    logs = []
    for record in [r for r in fleet.list_runs(unit=unit) if r.protocol == "short"]:
        r = fleet.open_run(record.run_id)
        log = UseLog.of_run(r)
        logs.append(write_use_log(log, tmp_path / f"use_{record.run_id}.h5"))
    plain = load_models(tmp_path / "plain").meta["codes"]
    got = calibrate_unit(run, unit, fleet, tmp_path / "logged", budget_seconds=40, use_seconds=15,
                         use_logs=logs)
    assert 0 < got.unlabeled_seconds <= 15 and got.unlabeled_samples == round(got.unlabeled_seconds * 200)
    assert not any(n.startswith("ordinary use:") for n in got.notes)  # the logs hold more than asked
    saved = load_models(tmp_path / "logged").meta
    assert saved["method"] == "response+use" and saved["codes"] != plain
    # asked for more than the logs hold, the rows weigh as the seconds they hold: the same codes as asked
    # for just those seconds, and a note says what was read of what was asked
    held = calibrate_unit(run, unit, fleet, tmp_path / "held", budget_seconds=40, use_seconds=600,
                          use_logs=logs, interval_level=0.8)
    exact = calibrate_unit(run, unit, fleet, tmp_path / "exact", budget_seconds=40,
                           use_seconds=held.unlabeled_seconds + 1e-3, use_logs=logs, interval_level=0.8)
    assert 15 < held.unlabeled_seconds < 600 and exact.unlabeled_samples == held.unlabeled_samples
    assert load_models(tmp_path / "held").meta["codes"] == load_models(tmp_path / "exact").meta["codes"]
    said = f"ordinary use: {held.unlabeled_seconds:.1f} s of contact read of the 600 s asked (all the logs"
    assert any(n.startswith(said) for n in held.notes)
    assert held.intervals["fleet_factor"] == exact.intervals["fleet_factor"]  # weighed alike: one factor
    assert any("the plan alone's fleet factor" in n for n in held.notes) == (held.unlabeled_seconds < 20)
    other = next(u for u in {r.unit for r in fleet.list_runs()} if u != unit)
    stranger = write_use_log(replace(log, sensor_id=other), tmp_path / "stranger.h5")
    with pytest.raises(AnytipError, match=f"stranger.h5: a log of {other}"):
        calibrate_unit(run, unit, fleet, tmp_path / "x", budget_seconds=40, use_seconds=15,
                       use_logs=[stranger])
    with pytest.raises(AnytipError, match="give --ordinary-use SECONDS"):
        calibrate_unit(run, unit, fleet, tmp_path / "y", budget_seconds=40, use_logs=logs)
    still = write_use_log(replace(log, pressure=np.full_like(log.pressure, 1e5)), tmp_path / "still.h5")
    with pytest.raises(AnytipError, match="ordinary-use logs hold no contacts"):
        calibrate_unit(run, unit, fleet, tmp_path / "z", budget_seconds=40, use_seconds=15, use_logs=[still])
    assert main(["calibrate", "--model", str(run), "--unit", unit, "--budget-seconds", "40", "--ordinary-use",
                 "15", "--use-log", *map(str, logs), "--registry", str(fleet.root),
                 "--out", str(tmp_path / "logged_cli")]) == 0


def test_the_fleet_code_encoder_learns_from_the_units_whose_ordinary_use_the_run_holds(fleet):
    """fleet_code_encoder: over the response model's units found in the given arrays (others
    skipped), each one's stream features of its ordinary use against its codes; codes along the
    features' first principal direction are explained and predicted, codes unrelated to them give
    no encoder (the search starts from codes zero), nor do fewer than three units."""
    from anytip.data.arrays import load_arrays
    from anytip.train.code_encoder import CodeEncoder, stream_features
    from anytip.train.label_free import fleet_code_encoder, ordinary_rows

    arrays = load_arrays(fleet, [r for r in fleet.list_runs() if r.protocol == "short"])
    units, C = list(arrays.units), arrays.pressure.shape[1]
    F = np.stack([stream_features(arrays.pressure[ordinary_rows(arrays, u, "short", False, 20.0, 3)])
                  for u in units])
    U, S, _ = np.linalg.svd((F - F.mean(0)) / np.maximum(F.std(0), 1e-9), full_matrices=False)
    codes = np.stack([np.outer(np.ones(C), [p, -p]) for p in U[:, 0] * S[0]]) * 0.05

    def fit_with(Z: np.ndarray, ids: list[str]) -> ResponseFit:
        model = ResponseModel(len(ids), C, 5, [0, 1, 2], ResponseConfig(code_dim=2, channel_dim=2, hidden=8,
                                                                         layers=1), seed=0)
        with torch.no_grad():
            model.codes.copy_(torch.from_numpy(Z).float())
        return ResponseFit(model, torch.full((C,), 1e-4), torch.full((2,), 0.04), ids)

    ghost = np.zeros((1, C, 2))  # a unit the arrays do not hold: skipped
    coder = fleet_code_encoder(fit_with(np.concatenate([codes, ghost]), [*units, "ghost"]), [arrays],
                               "short", False, 20.0, 3)
    assert coder is not None and coder.loo_r2 > 0.5
    same = CodeEncoder.fit(F, codes.astype(np.float32), np.full(2, 0.04, np.float32))
    np.testing.assert_allclose(coder.weights, same.weights, rtol=1e-4, atol=1e-6)
    noise = np.random.default_rng(0).normal(size=codes.shape) * 0.2
    assert fleet_code_encoder(fit_with(noise, units), [arrays], "short", False, 20.0, 3) is None
    assert fleet_code_encoder(fit_with(codes[:2], units[:2]), [arrays], "short", False, 20.0, 3) is None


def test_the_force_scale_prior_reads_the_training_units_ordinary_use(fleet):
    """fleet_force_scale: over the given units' ordinary use (whole presses of their calibration
    streams, labels read), the mean and spread of the rows' mean square force; a sensor model
    without a force target has none, and one unit gives no spread."""
    from anytip.data.plans import ordinary_use, ordinary_use_seed
    from anytip.train.label_free import LabelFreeRecipe, fleet_force_scale

    arrays = load_arrays(fleet, [r for r in fleet.list_runs() if r.protocol == "short"])
    units, free = arrays.units[:4], LabelFreeRecipe(seconds=20.0, rows=10**6)
    scale = fleet_force_scale(arrays, units, "short", False, free, 3)
    each = []
    for u in units:
        stream = calibration_stream(arrays, u, "short")
        presses = find_presses(arrays, u, stream.outside(arrays))
        rows = ordinary_use(presses, 20.0, ordinary_use_seed(3, u)).rows
        each.append((arrays.targets[rows, :3].astype(np.float64) ** 2).sum(1).mean())
    assert scale is not None and scale.columns == (0, 1, 2)
    assert scale.mean == pytest.approx(np.mean(each), rel=1e-5)
    assert scale.var == pytest.approx(np.var(each, ddof=1), rel=1e-4)
    angles = replace(arrays, layout={"angles": arrays.layout["angles"]})
    assert fleet_force_scale(angles, units, "short", False, free, 3) is None
    with pytest.raises(ValueError, match="at least two units"):
        fleet_force_scale(arrays, units[:1], "short", False, free, 3)


def test_label_free_codes_learns_the_encoder_from_units_that_only_teach_it(fleet, tmp_path):
    """--encoder-units: another registry's units teach the `encoder_more` arm only (their codes fitted
    by the frozen response model); a toward_all_<t> arm lies between the encoder's codes and the
    whole stream's; a unit shared with the run's registry, or the arm without the registry, is refused."""
    over = [*SECONDS, RESPONSE.replace("}", ", inverse_start: pooled}"), "options.adapters=[]"]
    from anytip.data.simulated import simulate_into
    from anytip.sensor.fleet import FleetConfig
    from test_cross_sensor import QUICK

    run = run_experiment(SPEC, fleet, out=tmp_path / "run", overrides=over, progress=False)
    more = Registry(tmp_path / "more")
    simulate_into(more, FleetConfig(), 3, seed=12, protocols=(QUICK,))
    script = _script("label_free_codes")
    out = tmp_path / "codes.json"
    args = [str(run), "--registry", str(fleet.root), "--out", str(out), "--rows", "256"]
    arms = "input_stats,encoder,encoder_more,all_labels,toward_all_0.5"
    assert script.main([*args, "--arms", arms, "--encoder-units", str(more.root)]) == 0
    rows = json.loads(out.read_text())["rows"]
    assert {r["arm"] for r in rows} == set(arms.split(","))
    by = {(r["unit"], r["arm"]): r for r in rows}
    for u in {r["unit"] for r in rows}:
        assert by[u, "toward_all_0.5"]["test_residual_pa"] > 0 and by[u, "input_stats"]["force_rmse_n"] > 0
        assert "code_rms_encoder_more_off_all" in by[u, "encoder_more"]
    curve = json.loads(out.read_text())["encoder_r2_by_units"]["0"]
    assert curve and all(len(r) == 1 and r[0] <= 1 for r in curve.values())
    spread = tmp_path / "spread.json"  # ordinary use spread over the stream, for new and teaching units alike
    assert script.main([str(run), "--registry", str(fleet.root), "--out", str(spread), "--rows", "256",
                        "--arms", arms, "--encoder-units", str(more.root), "--unlabeled", "spread",
                        "--seconds", "20"]) == 0
    found = json.loads(spread.read_text())
    assert found["unlabeled"] == "spread" and {r["arm"] for r in found["rows"]} == set(arms.split(","))
    again = {(r["unit"], r["arm"]): r for r in found["rows"]}
    assert any(again[k]["code_rms_encoder_off_truth"] != by[k]["code_rms_encoder_off_truth"]
               for k in by if k[1] == "encoder")
    with pytest.raises(SystemExit):
        script.main([*args, "--arms", "encoder_more"])
    with pytest.raises(SystemExit):
        script.main([*args, "--arms", "encoder,toward_all_0.5"])
    assert script.main([*args, "--arms", "encoder,encoder_more", "--encoder-units", str(fleet.root)]) == 2


def test_transfer_check_scores_a_second_interval_from_residuals_the_network_never_saw(fleet, tmp_path):
    """`intervals.transfer_check`: a network per unit on its transferred rows alone; its residuals on
    the plan's rows give `transfer_` intervals with their own factor, and the validation units'
    spread of log(needed / own) is recorded for both kinds."""
    over = [*SECONDS, RESPONSE, "options.adapters=[]", "splits.n_val_units=2",
            "options.intervals={folds: 3, level: 0.8, transfer_check: true}"]
    run = run_experiment(SPEC, fleet, out=tmp_path / "run", overrides=over, progress=False)
    rows = [r for r in json.loads((run / "metrics.json").read_text())["results"] if "fx_fleet_coverage" in r]
    assert rows and all(0 <= r["fx_transfer_coverage"] <= 1 and r["fx_transfer_halfwidth"] > 0 for r in rows)
    assert any(r["fx_transfer_halfwidth"] != r["fx_fleet_halfwidth"] for r in rows)
    spread = load_response(run / "models" / "response_seed0.safetensors").meta["intervals"]
    kinds = spread["log_ratio_spread_by_strategy"]
    assert set(kinds) == {"plan", "transfer"}
    assert all(v >= 0 for by in kinds["transfer"].values() for b in by.values() for v in b.values())
    assert "network of the transferred rows alone" in (run / "report.md").read_text()


def test_factor_units_learn_the_fleet_factor_beside_the_validation_units(fleet, tmp_path):
    """`intervals.factor_units`: units the split leaves over after its training units are calibrated
    as validation units are, by the plan alone and with ordinary use; they learn the fleet factor
    and its leave-one-out margin and choose nothing else: the held-out rows keep their errors and
    their plan's own half-widths, and calibrate applies the recorded margin and says so."""
    free = ("label_free: {seconds: 20, rows: 64, candidates: 256, rounds: 1, iterations: 2, "
            "with_plans: true, zero_shot: false}")
    base = [*SECONDS, RESPONSE.replace("}", f", inverse_start: pooled, {free}}}"), "splits.n_train_units=3",
            "options.adapters=[input_affine]", "options.fits=[{}]"]  # calibrate needs a shared model
    runs = {k: run_experiment(SPEC, fleet, out=tmp_path / f"f{k}", progress=False, overrides=[
        *base, f"options.intervals={{folds: 3, level: 0.8, factor_units: {k}}}"]) for k in (0, 2)}
    split = {k: json.loads((r / "provenance.json").read_text())["cross_sensor"]["seed0"]["units"]
             for k, r in runs.items()}
    assert {k: split[2][k] for k in ("train", "val", "test")} == split[0] and len(split[2]["factor"]) == 2
    assert not set(split[2]["factor"]) & {u for k in ("train", "val", "test") for u in split[2][k]}
    rows = {k: [r for r in json.loads((run / "metrics.json").read_text())["results"] if "interval_level" in r]
            for k, run in runs.items()}
    assert rows[0] and len(rows[0]) == len(rows[2])
    for a, b in zip(rows[0], rows[2], strict=True):
        assert (a["unit"], a["method"], a["force_rmse_n"], a["fx_halfwidth"]) == \
               (b["unit"], b["method"], b["force_rmse_n"], b["fx_halfwidth"])
        assert b["fx_needed70_halfwidth"] <= b["fx_needed75_halfwidth"] <= b["fx_needed85_halfwidth"]
        assert b["fx_margin_halfwidth"] >= b["fx_fleet_halfwidth"] > 0
    assert any(a["fx_fleet_halfwidth"] != b["fx_fleet_halfwidth"]
               for a, b in zip(rows[0], rows[2], strict=True))
    meta = load_response(runs[2] / "models" / "response_seed0.safetensors").meta["intervals"]
    assert meta["factor_units"] == 2
    for key in ("units_by_strategy", "use_units_by_strategy"):
        learnt = meta[key]["spread"]
        assert all(set(by) == {*split[2]["val"], *split[2]["factor"]} for by in learnt.values())
    margins = meta["margin_by_strategy"]["spread"]
    assert all(m["margin"] >= 1 and set(m["below_floor"]) == set(m["in_band"]) for m in margins.values())
    # calibrate multiplies the fleet factor by the recorded margin
    unit, response = split[2]["test"][0], runs[2] / "models" / "response_seed0.safetensors"
    before = calibrate_unit(runs[2], unit, fleet, tmp_path / "c0", budget_seconds=40, method="response",
                            interval_level=0.8)
    header = json.loads(response.with_suffix(".json").read_text())
    for m in header["meta"]["intervals"]["margin_by_strategy"]["spread"].values():
        m["margin"] = 1.5
    response.with_suffix(".json").write_text(json.dumps(header))
    after = calibrate_unit(runs[2], unit, fleet, tmp_path / "c1", budget_seconds=40, method="response",
                           interval_level=0.8)
    assert before.intervals is not None and after.intervals is not None
    for name, half in after.intervals["halfwidth"].items():
        assert half == pytest.approx(before.intervals["own_halfwidth"][name] * 1.5 *
                                     before.intervals["fleet_factor"][name] / _margin_of(before), rel=1e-6)
    assert any("the fleet factor times 1.5" in n for n in after.notes)
    # a record whose rule found no margin (every grid value leaves two left-out unit-outputs below the
    # floor): calibrate applies the factor alone and says why
    for m in header["meta"]["intervals"]["margin_by_strategy"]["spread"].values():
        # an entry that is no grid value or no number (a lab's hand-edited record) is left out, no traceback
        m["margin"], m["below_floor"] = 1.0, {**{g: 2 for g in m["below_floor"]}, "x": 0, "1.3": "none"}
    response.with_suffix(".json").write_text(json.dumps(header))
    bare = calibrate_unit(runs[2], unit, fleet, tmp_path / "c2", budget_seconds=40, method="response",
                          interval_level=0.8)
    assert bare.intervals is not None and not any(n.startswith("the fleet factor times ") for n in bare.notes)
    assert any("without a margin" in n and "2 left-out unit-output(s) stayed below the floor at every margin "
               "up to 1.2" in n for n in bare.notes)


def _margin_of(got) -> float:
    """The margin a calibration applied: 1 unless a note says otherwise."""
    said = [n for n in got.notes if n.startswith("the fleet factor times ")]
    return float(said[0].split()[4].rstrip(":")) if said else 1.0


def test_ordinary_use_distilled_into_the_units_network_is_a_method_of_its_own_in_the_run_and_calibrate(
        fleet, tmp_path):
    """`label_free.distil: fitted` (entry 78): the run's rows with ordinary use are
    `response+use+distil@`, chosen on their own validation loss; `anytip calibrate` reads the choice
    from the response model: the same codes as without it, another network, the method recorded;
    a model whose record says `oracle` (true contacts, a benchmark's ceiling) is refused by name."""
    free = ("label_free: {seconds: 20, rows: 64, candidates: 256, rounds: 1, iterations: 2, "
            "with_plans: true, zero_shot: false, distil: fitted, distil_repeat: 2}")
    over = [*SECONDS, RESPONSE.replace("}", f", inverse_start: pooled, {free}}}"), "splits.n_train_units=3",
            "options.adapters=[input_affine]", "options.fits=[{}]"]
    run = run_experiment(SPEC, fleet, out=tmp_path / "run", overrides=over, progress=False)
    methods = {r["method"].split("@")[0] for r in json.loads((run / "metrics.json").read_text())["results"]}
    assert "response+use+distil" in methods and "response+use" not in methods
    val = json.loads((run / "provenance.json").read_text())["cross_sensor"]["seed0"]["val_loss"]
    assert any(k.startswith("response+use+distil@") for k in val)
    unit, response = _held_out(run), run / "models" / "response_seed0.safetensors"
    calibrate_unit(run, unit, fleet, tmp_path / "fitted", budget_seconds=40, use_seconds=15)
    header = json.loads(response.with_suffix(".json").read_text())
    assert header["meta"]["label_free"]["recipe"]["distil"] == "fitted"
    header["meta"]["label_free"]["recipe"]["distil"] = "none"
    response.with_suffix(".json").write_text(json.dumps(header))
    calibrate_unit(run, unit, fleet, tmp_path / "none", budget_seconds=40, use_seconds=15)
    got = {k: load_models(tmp_path / k) for k in ("fitted", "none")}
    assert [got[k].meta["method"] for k in ("fitted", "none")] == ["response+use+distil", "response+use"]
    assert got["fitted"].meta["codes"] == got["none"].meta["codes"]
    assert not torch.equal(got["fitted"].model.weights[0], got["none"].model.weights[0])
    header["meta"]["label_free"]["recipe"]["distil"] = "oracle"
    response.with_suffix(".json").write_text(json.dumps(header))
    with pytest.raises(AnytipError, match=r"response_seed0.json: meta.label_free.recipe.distil: 'oracle'"):
        calibrate_unit(run, unit, fleet, tmp_path / "oracle", budget_seconds=40, use_seconds=15)
