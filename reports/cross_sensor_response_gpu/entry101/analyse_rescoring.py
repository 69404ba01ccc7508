"""Research log entry 101's reading of its rescorings: entry 99's analysis (`entry99/analyse.py`) with this
entry's runs as the arm, each paired with its registry's recipe as the control (other16: entry 97's
rescorings, 10 code steps; fleet88: entry 99's, the converged code fit). Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry101/analyse_rescoring.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
CONTROLS = {"other16": HERE.parent / "entry97", "fleet88": HERE.parent / "entry99"}
PLANS = ("cover", "cover_informative")


def main() -> None:
    reading = runpy.run_path(str(HERE.parent / "entry99" / "analyse.py"))
    registries = reading["REGISTRIES"]
    registries["fleet88"] = (*registries["fleet88"][:2], "cover_informative")  # entry 100's decision
    for name, control in CONTROLS.items():
        main_of = reading["main"]
        main_of.__globals__.update(HERE=HERE, CONTROL=control, REGISTRIES={name: registries[name]})
        main_of()


if __name__ == "__main__":
    main()
