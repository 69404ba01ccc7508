"""Research log entry 201's units and the network each is calibrated under, as entry 191 pairs its own:
SIM44-000 to 015 under fleet88 fold 0 and 016 to 031 under fold 1 (entry 147's at-120 runs); SIM26-(8K) to
(8K+7) under other16 fold K (entry 146's at-120 runs, start draw 0). Printed as `FOLD UNIT` lines for
`run.sh`.

    python reports/cross_sensor_response_gpu/entry201/units.py
"""

from __future__ import annotations

PAIRS = ([(f"f{i // 16}", f"SIM44-{i:03d}") for i in range(32)]
         + [(f"o{i // 8}", f"SIM26-{i:03d}") for i in range(32)])

if __name__ == "__main__":
    print("\n".join(f"{fold} {unit}" for fold, unit in PAIRS))
