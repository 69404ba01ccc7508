"""Research log entry 158: entry 107's `fresh_held_out.py` (a finished run's fold, fresh held-out units) with
each seed's response model read from MODEL (`{seed}`: the fold's seed) instead of the run's own, as
`scripts/rescore_response.py --response-model` reads it. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry158/fresh_severe.py MODEL RUN --registry REG \\
        --prefix SIM25- --units 0:32 --out OUT [--set KEY=VALUE ...]
"""

import runpy
import sys
from pathlib import Path

import anytip.models.io as io

if len(sys.argv) < 3:
    sys.exit(__doc__)
MODEL = sys.argv.pop(1)
read = io.load_response


def from_model(path: Path):
    """The response model of `path`'s seed (`.../response_seed<s>.safetensors`) read from MODEL."""
    seed = Path(path).stem.removeprefix("response_seed")
    return read(Path(MODEL.format(seed=seed)))


io.load_response = from_model
sys.argv[0] = "reports/cross_sensor_response_gpu/entry107/fresh_held_out.py"
runpy.run_path(sys.argv[0], run_name="__main__")
