"""Research log entry 103's reading: entry 99's analysis (`entry99/analyse.py`) with this entry's float32
kernel rescorings (`cover_informative` alone) as the arm, paired with entry 101's fleet88 runs of the same
folds as the control: the validation units' mean loss and per-unit ratio (rule 1), the held-out ratios and
the per-unit factor against entry 101 (rule 2). Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry103/analyse.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent


def main() -> None:
    reading = runpy.run_path(str(HERE.parent / "entry99" / "analyse.py"))
    plan = "cover_informative"
    runs = [("fleet88_cpu", k) for k in (0, 1)]
    main_of = reading["main"]
    main_of.__globals__.update(HERE=HERE, CONTROL=HERE.parent / "entry101",
                               REGISTRIES={"fleet88": (runs, [f"response@{plan}"], plan)})
    main_of()


if __name__ == "__main__":
    main()
