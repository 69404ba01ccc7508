"""Research log entry 190: `anytip calibrate` with a log of ordinary use weighed as the seconds asked
(`--ordinary-use`), whatever it holds: `FleetUse.n_effective` reads the seconds asked, which `_codes_from_use`
otherwise lowers to the seconds read. Nothing else changes.

    python reports/cross_sensor_response_gpu/entry190/as_asked.py SECONDS calibrate --model ... --out ...
"""

from __future__ import annotations

import sys

from anytip.cli import main
from anytip.train.label_free import FleetUse

if __name__ == "__main__":
    asked = float(sys.argv[1])
    FleetUse.n_effective = lambda self: asked * self.effective_hz  # type: ignore[method-assign]
    main(sys.argv[2:])
