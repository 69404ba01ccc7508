"""Heteroscedastic ensembles on a tiny fleet: coverage, export with scales, the pipeline."""

import json
from pathlib import Path

import numpy as np
import torch

from anytip.data.arrays import load_arrays
from anytip.models.io import load_models
from anytip.runner import run_experiment
from anytip.train.data import FleetBatchData, UnitTensors
from anytip.train.recipe import FAST
from anytip.uncertainty import conformal as cp
from anytip.uncertainty.ensembles import mixture, predict_members, train_hetero_fleet

REPO = Path(__file__).resolve().parents[1]
TINY = FAST.model_copy(update={"epochs": 3, "batch_size": 128})
TINY_SPEC = ["seeds=[0]", "data.protocol=short", "training.epochs=2", "training.batch_size=128",
             "options.members=2", "options.max_train_rows=3000", "options.foreign_units=1",
             "options.max_detect_rows=2000", "options.windows=[100]", "options.cv_folds=3",
             "options.rest_block_rows=300", "options.rest_reference_rows=1000",
             "options.adapted={epochs: 1, budget: 500, calib_rows: 500, members: 2}"]


def _random_roles(arrays, units, seed=0):
    """Per unit: fit / val / calibration / test rows drawn at random (exchangeable)."""
    members, cal, test = [], [], []
    for u in units:
        rows = np.random.default_rng(seed + u).permutation(np.flatnonzero(arrays.unit == u))[:8000]
        fit, val, c, t = np.split(rows, [4000, 4500, 6000])
        y = arrays.targets
        members.append(UnitTensors(torch.from_numpy(arrays.pressure[fit]), torch.from_numpy(y[fit]),
                                   torch.from_numpy(arrays.pressure[val]), torch.from_numpy(y[val]),
                                   arrays.units[u]))
        cal.append(c)
        test.append(t)
    return FleetBatchData.from_units(members), cal, test


def test_conformal_ensemble_covers_each_unit_of_a_tiny_fleet(small_registry):
    arrays = load_arrays(small_registry, small_registry.list_runs())
    data, cal, test = _random_roles(arrays, [0, 1])
    fit = train_hetero_fleet(data, recipe=TINY, n_members=2, seed=0)
    assert fit.model.n_models == 4 and fit.model.config.sizes[-1] == 10
    for u in range(2):
        mu_c, sig_c = predict_members(fit, u, arrays.pressure[cal[u]])
        mu_t, sig_t = predict_members(fit, u, arrays.pressure[test[u]])
        (m_c, s_c, _), (m_t, s_t, _) = mixture(mu_c, sig_c), mixture(mu_t, sig_t)
        q = cp.conformal_quantile(cp.scores_of(m_c, arrays.targets[cal[u]], s_c), 0.1)
        cov = cp.coverage(*cp.interval(m_t, q, s_t), arrays.targets[test[u]])
        # 2000 exchangeable test rows per unit: within 0.04 of nominal for every output
        assert np.all(np.abs(cov - 0.9) < 0.04), cov


def test_saved_model_carries_its_scale_outputs(small_registry, tmp_path):
    arrays = load_arrays(small_registry, small_registry.list_runs())
    data, _, test = _random_roles(arrays, [0, 1])
    fit = train_hetero_fleet(data, recipe=TINY.model_copy(update={"epochs": 1}), n_members=2)
    loaded = load_models(fit.save(tmp_path / "m.safetensors"))
    assert loaded.meta["scale_outputs"] == [5, 6, 7, 8, 9] and loaded.model.n_models == 4
    x = torch.from_numpy(arrays.pressure[test[1][:50]])
    z = loaded.model.model_slice(3)(loaded.in_scaler.slice(3).transform(x[None]))[0]
    out = loaded.out_scaler.slice(3).inverse(z[None])[0]
    sigma = torch.exp(0.5 * out[:, 5:])  # physical log-variances: no scaler needed
    mu_ref, sig_ref = predict_members(fit, 1, x.numpy())
    np.testing.assert_allclose(out[:, :5].detach().numpy(), mu_ref[1], rtol=1e-4, atol=1e-4)
    np.testing.assert_allclose(sigma.detach().numpy(), sig_ref[1], rtol=1e-4, atol=1e-6)


def test_pipeline_rows_and_stuck_channel_is_flagged(small_registry, tmp_path):
    spec = REPO / "experiments" / "uncertainty.yaml"
    out = run_experiment(spec, small_registry, out=tmp_path / "run", overrides=TINY_SPEC, progress=False)
    rows = json.loads((out / "metrics.json").read_text())["results"]
    cov = [r for r in rows if "coverage" in r]
    assert {r["nominal_coverage"] for r in cov} == {0.5, 0.9, 0.95}
    assert {"hetero", "ensemble", "conformal", "ensemble+conformal", "mapie"} <= {r["method"] for r in cov}
    assert all(0 <= r["coverage"] <= 1 and r["interval_width"] > 0 for r in cov)
    gap = [abs(r["mapie_minus_own_width"]) for r in rows if "mapie_minus_own_width" in r]
    assert max(gap) < 1e-9
    stuck = [r["auroc"] for r in rows
             if r.get("fault") == "stuck_channel" and r["method"] == "detect:flatline"]
    assert len(stuck) == 8 and min(stuck) > 0.99
    assert (out / "report.md").exists() and (out / "calibration_curves.png").exists()
    adapted = {r["unit"] for r in cov if r["method"].endswith("conformal:val_units")}
    assert len(adapted) == 4  # the held-out units of the shared model
    methods = {r["method"] for r in cov}
    assert {"cv+conformal", "cv+hetero+conformal", "adapted:input_affine+film+scale+conformal:val_units",
            "adapted:input_affine+film+scale+conformal:budget", "adapted:input_affine+film+ensemble",
            "adapted:input_affine+film+ensemble+conformal:val_units"} <= methods
    het = [r for r in cov if r["method"] == "adapted:input_affine+film+hetero"]
    assert len({r["unit"] for r in het}) == 4 and all(r["nll"] is not None for r in het)
    assert {"adapted:input_affine+film+hetero+conformal:val_units",
            "adapted:input_affine+film+hetero+conformal:budget"} <= methods
    saved = load_models(out / "models" / "adapted_hetero_seed0")
    assert saved.model.n_models == 4 and saved.meta["scale_outputs"] == [5, 6, 7, 8, 9]
    assert sorted(saved.meta["unit_ids"]) == sorted({r["unit"] for r in het})
    ens = [r for r in cov if r["method"] == "adapted:input_affine+film+ensemble"]
    assert len({r["unit"] for r in ens}) == 4 and all(r["members"] == 2 for r in ens)
    assert any(r.get("method") == "detect:rest_drift:other_runs" for r in rows)
    drift = [r for r in rows if r.get("method") == "detect:rest_drift"]
    assert {r["fault"] for r in drift} == {f"drift_{c}_{a}kPa" for c in ("all", "one") for a in (1, 3)}
    boot = [r for r in rows if "bootstrap" in r]
    assert boot and all(0 <= r["exact_p_outside"] <= 1 and r["exact_lo"] <= r["exact_hi"] for r in boot)


def _rowset(x: np.ndarray) -> set[bytes]:
    return {r.tobytes() for r in np.ascontiguousarray(x)}


def test_calibration_and_test_patches_never_reach_training(small_registry):
    from anytip.uncertainty.split import uq_split

    arrays = load_arrays(small_registry, small_registry.list_runs())
    split = uq_split(arrays, None, 0.2, 0.2, 0.1, 0, torch.device("cpu"))
    for u in range(len(arrays.units)):
        member = split.data.unit(u)
        seen = _rowset(member.X_train.numpy()) | _rowset(member.X_val.numpy())
        cal, test = _rowset(split.X_cal[u]), _rowset(split.X_test[u])
        assert len(cal) and len(test) and not (seen & cal) and not (seen & test) and not (cal & test)


def test_unknown_option_names_the_key(small_registry, tmp_path):
    import pytest

    from anytip.errors import AnytipError

    spec = REPO / "experiments" / "uncertainty.yaml"
    with pytest.raises(AnytipError, match="options.*membres"):
        run_experiment(spec, small_registry, out=tmp_path / "bad", overrides=["options.membres=3"],
                       progress=False)


def test_saved_scale_outputs_are_physical_log_variances():
    """Standardised log-variance z and std s give log(s^2 e^z) = z + 2 log s after the saved
    scaler, so sigma = exp(0.5 * output) in N or rad on the device."""
    import torch

    from anytip.models.heteroscedastic import output_scaler_2d, to_physical
    from anytip.models.scaler import Scaler

    s = Scaler(torch.tensor([[[1.0, -2.0]]]), torch.tensor([[[3.0, 0.5]]]))
    z = torch.tensor([[[0.2, -0.3, 0.7, -1.1]]])
    out = output_scaler_2d(s).inverse(z)
    _, sigma = to_physical(z[..., :2], z[..., 2:], s)
    torch.testing.assert_close(torch.exp(0.5 * out[..., 2:]), sigma)


def test_cross_conformal_covers_each_unit_of_a_tiny_fleet(small_registry):
    """K fold models as one batched fleet; out-of-fold normalised scores calibrate a fold
    model drawn per test row. Groups of rows stand in for patches; test rows are exchangeable."""
    from anytip.uncertainty.cross_conformal import out_of_fold, patch_folds, pick_fold_model

    arrays = load_arrays(small_registry, small_registry.list_runs())
    K, members, folds, rest_rows, test_rows = 3, [], [], [], []
    for u in (0, 1):
        rows = np.random.default_rng(10 + u).permutation(np.flatnonzero(arrays.unit == u))[:9000]
        rest, test = rows[:6000], rows[6000:8000]
        fold = patch_folds(np.arange(len(rest)) % 60, K, seed=u)
        assert sorted(np.bincount(fold).tolist()) == [2000, 2000, 2000]
        for k in range(K):
            train = rest[fold != k]
            members.append(UnitTensors(torch.from_numpy(arrays.pressure[train[:3600]]),
                                       torch.from_numpy(arrays.targets[train[:3600]]),
                                       torch.from_numpy(arrays.pressure[train[3600:]]),
                                       torch.from_numpy(arrays.targets[train[3600:]]), f"{u}/{k}"))
        folds.append(fold)
        rest_rows.append(rest)
        test_rows.append(test)
    fit = train_hetero_fleet(FleetBatchData.from_units(members), recipe=TINY, n_members=1, seed=0)
    for u in (0, 1):
        pred_r = [tuple(a[0] for a in predict_members(fit, u * K + k, arrays.pressure[rest_rows[u]]))
                  for k in range(K)]
        mu_c, sig_c = out_of_fold(pred_r, folds[u])
        pred_t = [tuple(a[0] for a in predict_members(fit, u * K + k, arrays.pressure[test_rows[u]]))
                  for k in range(K)]
        mu_t, sig_t = pick_fold_model(pred_t, np.random.default_rng(u))
        q = cp.conformal_quantile(cp.scores_of(mu_c, arrays.targets[rest_rows[u]], sig_c), 0.1)
        cov = cp.coverage(*cp.interval(mu_t, q, sig_t), arrays.targets[test_rows[u]])
        # 6000 out-of-fold scores, 2000 exchangeable test rows: within 0.04 of nominal
        assert np.all(np.abs(cov - 0.9) < 0.04), cov
