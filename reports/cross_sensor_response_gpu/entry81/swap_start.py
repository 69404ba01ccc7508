"""`scripts/rescore_response.py` with the pooled start network replaced by another run's saved one
(research log entry 81, third part): the start network trains as usual, then takes the saved
weights, so every unit's network starts where that run's did. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry81/swap_start.py SAVED_START.safetensors RUN \\
        --registry REG --out OUT [rescore_response.py's options]

The saved network must have been trained on the same source rows (its scalers are checked).
"""

import runpy
import sys
from pathlib import Path

import torch

import anytip.pipelines.cross_sensor_response as pipe
from anytip.models.io import load_models

if len(sys.argv) < 3 or not Path(sys.argv[1]).is_file():
    sys.exit(__doc__)
SAVED = Path(sys.argv.pop(1))
trained = pipe.start_network


def swapped(*args, **kwargs):
    """The start network `start_network` trains, its weights replaced by SAVED's."""
    fit = trained(*args, **kwargs)
    saved = load_models(SAVED)
    same_rows = torch.equal(fit.in_scaler.mean, saved.in_scaler.mean)
    if not (same_rows and torch.equal(fit.out_scaler.std, saved.out_scaler.std)):
        sys.exit(f"{SAVED}: its scalers differ from the start network's: trained on other rows")
    with torch.no_grad():
        for mine, theirs in zip(fit.model.parameters(), saved.model.parameters(), strict=True):
            mine.copy_(theirs)
    print(f"start network swapped for {SAVED}", flush=True)
    return fit


pipe.start_network = swapped
sys.argv[0] = "scripts/rescore_response.py"
runpy.run_path("scripts/rescore_response.py", run_name="__main__")
