"""Fitting many units at once, the one-at-a-time reference, and metrics."""

from anytip.train.data import FleetBatchData, UnitSampler, UnitTensors, pad_rows, split_rows
from anytip.train.fleet import FitResult, train_fleet
from anytip.train.metrics import (
    angle_rmse,
    evaluate,
    force_rmse,
    force_rmse_per_axis,
    predict,
    rmse_per_output,
)
from anytip.train.recipe import FAST, PAPER, RECIPES, TrainRecipe, get_recipe, lr_at
from anytip.train.sequential import train_sequential
from anytip.train.timing import time_to_target

__all__ = [
    "FAST", "PAPER", "RECIPES", "FitResult", "FleetBatchData", "TrainRecipe", "UnitSampler",
    "UnitTensors", "angle_rmse", "evaluate", "force_rmse", "force_rmse_per_axis", "get_recipe",
    "lr_at", "pad_rows", "predict", "rmse_per_output", "split_rows", "time_to_target",
    "train_fleet", "train_sequential",
]
