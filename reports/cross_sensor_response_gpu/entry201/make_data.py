"""Research log entry 201: 64 fresh units and their logs, made as entry 191 made its own. `data/test201d`: a
copy of `data/fleet88p` (payloads linked, catalog copied) with 32 more default fingertips (seed 44,
SIM44-000 to 031, never drawn before) pressed through the full protocol and the designed 120 s plan;
`data/test201o`: a copy of `data/other16p` with 32 more units of the other elastomer (seed 26, SIM26-000
to 031, never drawn before). Each new unit's session of ordinary use (entry 177's `use` protocol) is
written as ordinary-use logs under `build/entry201_logs/`.

    python reports/cross_sensor_response_gpu/entry201/make_data.py > \\
        reports/cross_sensor_response_gpu/entry201/logs/data.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

HERE = Path(__file__).parent
E191 = runpy.run_path(str(HERE.parent / "entry191" / "make_data.py"))

if __name__ == "__main__":
    E191["main"](Path("build/entry201_logs"), (("data/fleet88p", "data/test201d", None, 44),
                                               ("data/other16p", "data/test201o",
                                                "configs/fleets/other_elastomer.yaml", 26)))
