"""Input feature maps: the neighbour pairs of the dome, and folding the features and their
scaler into the first layer without changing the network's outputs."""

import numpy as np
import pytest
import torch

from anytip.errors import AnytipError
from anytip.models.features import feature_matrix, fold_features, neighbour_pairs
from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.models.scaler import Scaler
from anytip.search.fit import feature_tensor, map_fleet, train_candidate
from anytip.search.study import Candidate
from anytip.train.data import FleetBatchData, split_rows
from anytip.train.fleet import train_fleet
from anytip.train.metrics import predict
from anytip.train.recipe import FAST


def test_neighbours_form_a_ring_around_both_boards():
    pairs = neighbour_pairs()
    assert len(pairs) == 8
    degree = np.bincount(np.array(pairs).ravel(), minlength=8)
    assert degree.tolist() == [2] * 8  # every barometer has two neighbours: one cycle of 8
    assert (0, 4) in pairs and (1, 5) in pairs  # across the corner between the boards


def test_feature_matrix_and_unknown_name():
    F = feature_matrix("neighbour_diffs")
    assert F.shape == (8, 16) and np.allclose(F[:, :8], np.eye(8)) and np.allclose(F[:, 8:].sum(0), 0)
    with pytest.raises(AnytipError, match="unknown input features 'pca'.*neighbour_diffs"):
        feature_matrix("pca")


@pytest.mark.parametrize("activation", ["relu", "hardswish", "leaky_relu"])
def test_folded_network_equals_the_feature_network(activation):
    g = torch.Generator().manual_seed(0)
    F = feature_tensor("neighbour_diffs")
    model = BatchedMLP(3, MLPConfig(sizes=(16, 12, 24, 5), activation=activation), seed=1)
    x = 300 * torch.randn(3, 500, 8, generator=g)  # tared pressures, Pa
    feats = x @ F
    scaler = Scaler.fit(feats)
    raw = Scaler.fit(x)
    folded, raw_out = fold_features(model, scaler, F, raw)
    assert folded.config.sizes == (8, 12, 24, 5) and folded.config.activation == activation
    with torch.no_grad():
        want = model(scaler.transform(feats))
        got = folded(raw_out.transform(x))
    assert want.abs().max() > 0.1
    assert torch.allclose(got, want, atol=1e-5, rtol=0)


def test_trained_candidate_is_returned_folded_with_the_same_outputs():
    g = np.random.default_rng(0)
    units = []
    for u in range(2):
        X = (200 * g.standard_normal((400, 8))).astype(np.float32)
        Y = np.tanh(X[:, :5] / 200 - X[:, 3:] / 300).astype(np.float32)
        units.append(split_rows(X, Y, 0.2, seed=u, unit_id=str(u)))
    data = FleetBatchData.from_units(units)
    recipe = FAST.model_copy(update={"epochs": 2, "batch_size": 64})
    cand = Candidate((8, 16, 5), "hardswish", "neighbour_diffs")
    fit = train_candidate(data, cand, recipe, seed=0)
    assert fit.model.config.sizes == (8, 16, 5) and fit.in_scaler.mean.shape == (2, 1, 8)
    F = feature_tensor("neighbour_diffs")
    unfolded = train_fleet(map_fleet(data, F), MLPConfig(sizes=(16, 16, 5), activation="hardswish"),
                           recipe, seed=0)
    with torch.no_grad():
        pred = predict(fit.model, fit.in_scaler, fit.out_scaler, data.X_val)
        want = predict(unfolded.model, unfolded.in_scaler, unfolded.out_scaler, data.X_val @ F)
    assert torch.allclose(pred, want, atol=1e-5, rtol=0)
