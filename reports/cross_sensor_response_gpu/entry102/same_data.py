"""Research log entry 102, rule 1's search for a cause: do the runs fleet88 and fleet88p share load with the
same pressures, targets and forces, row for row, under fold 0's spec? Prints the count of runs that differ
(`logs/same_data.log`). Usage, from the repository root (about 10 minutes, two loads of the fleet):

    python reports/cross_sensor_response_gpu/entry102/same_data.py
"""

from pathlib import Path

import numpy as np
import torch

from anytip.config import load_spec
from anytip.data.registry import Registry
from anytip.pipelines.common import Context, load
from anytip.pipelines.cross_sensor import min_units

RUN = Path("reports/cross_sensor_response_start/fleet88_seed0")
FIELDS = ("targets", "pressure", "force")


def arrays(registry: str, overrides: list[str]):
    spec = load_spec(RUN / "config.yaml", [*overrides, "options.adapters=[]"])
    ctx = Context(spec, Registry(Path(registry), create=False), Path("build/same_data"), torch.device("cpu"),
                  False, {"spec_file": str(RUN / "config.yaml")})
    return load(ctx, min_units(ctx))


def main() -> None:
    a = arrays("data/fleet88", [])
    b = arrays("data/fleet88p", ["data.protocol=[full, short, quick, plan120]"])
    in_b = {r.run_id: j for j, r in enumerate(b.runs)}
    differ = dict.fromkeys(FIELDS, 0)
    for i, run in enumerate(a.runs):
        ra, rb = np.flatnonzero(a.run == i), np.flatnonzero(b.run == in_b[run.run_id])
        for f in FIELDS:
            differ[f] += len(ra) != len(rb) or not np.array_equal(getattr(a, f)[ra], getattr(b, f)[rb])
    print(f"{len(a.runs)} shared runs; runs that differ: {differ}")


if __name__ == "__main__":
    main()
