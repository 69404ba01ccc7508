"""Entry 101's `same_rows.py` (the run's recorded registry hash taken from the registry simulated again)
with entry 92's `force_cells.py` (`cover_informative`'s cells kept to one force level) for research log
entry 156: each of those wrappers ends in running `scripts/rescore_response.py`; here the first wrapper's
call runs the second instead, which then runs the script. Usage, from the repository root, as
`same_rows.py`:

    python reports/cross_sensor_response_gpu/entry156/same_rows_force_cells.py [...] RUN --registry REG \
        --out OUT
"""

import runpy
from pathlib import Path

GPU = Path(__file__).resolve().parent.parent
run_path = runpy.run_path


def chained(path: str, *args, **kwargs):
    """runpy.run_path, with `scripts/rescore_response.py` run through `force_cells.py` the first time."""
    if path == "scripts/rescore_response.py":
        runpy.run_path = run_path
        path = str(GPU / "entry90" / "force_cells.py")
    return run_path(path, *args, **kwargs)


runpy.run_path = chained
run_path(str(GPU / "entry101" / "same_rows.py"), run_name="__main__")
