"""`scripts/rescore_response.py` on a registry simulated again from the run's own command (research log
entry 101): the simulator's runs are written anew, so their files' bytes, and with them the registry's
content hash, differ from those the run recorded, and the rescoring refuses them. This wrapper takes
the hash of the same run ids in the registry given as the run's, and the reproduction check written
down with the entry (the control rescored this way must give its committed rows back, bit for bit)
stands for the data's identity. The new run's provenance records the registry's real hashes. Usage,
from the repository root, as `scripts/rescore_response.py`:

    python reports/cross_sensor_response_gpu/entry101/same_rows.py [...] RUN --registry REG --out OUT [...]
"""

import runpy
import sys
from pathlib import Path

import anytip.rundir as rundir
from anytip.data.registry import Registry

read = rundir.read_json
at = sys.argv.index("--registry")
registry, run = Path(sys.argv[at + 1]), Path(sys.argv[at - 1]).resolve()  # RUN is given just before it


def as_recorded(path: Path):
    """The run's provenance with its selection hash that of its runs in `registry`."""
    got = read(path)
    if Path(path).resolve() == run / "provenance.json":
        got = {**got, "selection_content_hash": Registry(registry, create=False).content_hash(got["runs"])}
    return got


rundir.read_json = as_recorded
sys.argv[0] = "scripts/rescore_response.py"
runpy.run_path("scripts/rescore_response.py", run_name="__main__")
