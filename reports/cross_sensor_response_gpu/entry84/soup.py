"""`scripts/rescore_response.py` with each new unit's network a weight average of K networks
(research log entry 84): every job trains as K members of the batched fleet, each from the pooled
start network with its own validation rows and batch draws for `inverse_epochs` / K epochs (the
same steps in all), and the unit's network is the mean of the K members' kept weights. The pooled
start network and the interval checks train as before. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry84/soup.py K RUN --registry REG --out OUT \\
        [rescore_response.py's options]
"""

import runpy
import sys
from dataclasses import replace

import torch

import anytip.train.response as response
from anytip.models.mlp import BatchedMLP
from anytip.train.fleet import FitResult

if len(sys.argv) < 3 or not sys.argv[1].isdigit() or int(sys.argv[1]) < 1:
    sys.exit(__doc__)
K = int(sys.argv.pop(1))
trained = response.unit_networks


def mean_of_members(fit: FitResult, k: int, ids: list[str]) -> FitResult:
    """The fleet of len(ids) networks whose weights are the means of fit's members m*k .. m*k+k-1."""
    m = len(ids)
    souped = BatchedMLP(m, fit.model.config)
    with torch.no_grad():
        for mine, theirs in zip(souped.parameters(), fit.model.parameters(), strict=True):
            mine.copy_(theirs.reshape(m, k, *theirs.shape[1:]).mean(1))
    first = list(range(0, m * k, k))  # every member starts from the same scalers: the start network's
    history = [{key: (v[::k] if isinstance(v, list) else v) for key, v in r.items()} for r in fit.history]
    return replace(fit, model=souped.to(fit.model.weights[0].device), in_scaler=fit.in_scaler.take(first),
                   out_scaler=fit.out_scaler.take(first), history=history, unit_ids=ids)


def souped(rows, shape, recipe, seed, ids, output_names, device, progress, start=None):
    """`unit_networks`, each job's network the mean of K members trained inverse_epochs / K epochs."""
    if start is None:
        return trained(rows, shape, recipe, seed, ids, output_names, device, progress, start)
    jobs = list(rows)
    ids = ids if ids is not None else [str(m) for m in range(len(jobs))]
    members = [job for job in jobs for _ in range(K)]
    member_ids = [f"{u}#{r}" for u in ids for r in range(K)]
    short = replace(recipe, inverse_epochs=max(1, recipe.inverse_epochs // K))
    fit = trained(members, shape, short, seed, member_ids, output_names, device, progress, start)
    print(f"soup: {len(jobs)} jobs x {K} members of {short.inverse_epochs} epochs", flush=True)
    return mean_of_members(fit, K, list(ids))


response.unit_networks = souped
sys.argv[0] = "scripts/rescore_response.py"
runpy.run_path("scripts/rescore_response.py", run_name="__main__")
