"""Research log entry 167: entry 164's references of a fold's fresh units from two more starts (3 and 4: the
fold's seed plus 3000 and 4000), everything else as entry 164 (`entry164/starts.py`, whose command line this
takes). Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry167/starts.py RUN --registry REG --prefix SIM25- \\
        --units 0:32 --out OUT [--set KEY=VALUE ...]
"""

import runpy

if __name__ == "__main__":
    runpy.run_path("reports/cross_sensor_response_gpu/entry164/starts.py")["main"](range(3, 5))
