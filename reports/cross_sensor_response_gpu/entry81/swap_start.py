"""rescore_response.py with the pooled start network replaced by another run's saved one (research log
entry 81's diagnostic): the network trains as usual, then takes the saved weights."""
import runpy, sys
from pathlib import Path
import torch
import anytip.pipelines.cross_sensor_response as pipe
from anytip.models.io import load_models

SAVED = Path(sys.argv.pop(1))
real = pipe.start_network

def swapped(*a, **k):
    fit = real(*a, **k)
    saved = load_models(SAVED)
    with torch.no_grad():
        for p, q in zip(fit.model.parameters(), saved.model.parameters(), strict=True):
            p.copy_(q)
    assert torch.equal(fit.in_scaler.mean, saved.in_scaler.mean) and torch.equal(fit.out_scaler.std, saved.out_scaler.std)
    print(f"start network swapped for {SAVED}", flush=True)
    return fit

pipe.start_network = swapped
sys.argv[0] = "scripts/rescore_response.py"
runpy.run_path("scripts/rescore_response.py", run_name="__main__")
