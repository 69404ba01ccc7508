"""`anytip calibrate`: a new unit's per-unit model from a shared model and minutes of data.

Takes the unit's calibration stream from the registry (its runs of the shared model's
calibration protocol, in recorded order), chooses its plan as the shared model's benchmark chose
plans (whole presses up to a number of robot seconds, data/plans.py, for models benchmarked in
seconds; else the first N rows of the stream; or the presses of the unit's runs of the designed
calibration, `--plan-strategy designed`), and calibrates it by one of two methods: the shared
model's adapter, fitted on the plan's labeled rows and folded into a plain MLP of the deployed
shape, or response transfer, which carries the training units' rows over to the unit through a
fleet model of each barometer's response identified on its plan (and its ordinary use). Either
way the unit's network is saved in the per-unit model format (models/io.py), which is what export
reads, with its own check and its intervals from the plan. Rows of the unit's other runs, which
calibration never touched, score the result when there are any.

- `unit`: `calibrate_unit`, the entry point (arguments checked, the method chosen);
- `records`: what the benchmark recorded (its run directory, shared and response models, tables);
- `plan_choice`: the budget's plan and the press selection response transfer takes;
- `adapter` and `response`: the two methods;
- `intervals`: the plan's half-widths times the fleet factor its benchmark learnt;
- `result`: what a calibration wrote (`Calibrated`, `calibration.json`) and the check on other runs.
"""

from anytip.calibrate.intervals import fleet_factor_for, plan_intervals
from anytip.calibrate.plan_choice import response_strategy
from anytip.calibrate.records import benchmarked_in, find_shared, response_models
from anytip.calibrate.result import OWN_CHECK_ALARM, Calibrated
from anytip.calibrate.unit import MAX_USE_S, METHODS, calibrate_unit

__all__ = ["MAX_USE_S", "METHODS", "OWN_CHECK_ALARM", "Calibrated", "benchmarked_in", "calibrate_unit",
           "find_shared", "fleet_factor_for", "plan_intervals", "response_models", "response_strategy"]
