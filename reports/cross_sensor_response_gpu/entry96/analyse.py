"""Research log entry 96's tables: a plan's codes fitted on rows weighted to the source rows' label cells
(`f`: |F| bands; `fp`: bands times place bins), against entry 91's MAP codes on the same plans: the
validation units' loss per fold and the held-out units paired per unit (`entry90/analyse.py`'s tables).
Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry96/analyse.py
"""

from pathlib import Path

from concordance import entry90  # this folder's: entry90/analyse.py as a module

HERE = Path(__file__).parent
GPU = HERE.parent
CELLS = ("f", "fp")


def main() -> None:
    tables = entry90()
    tables.show("other16, default-spread models", "other16_seed", (0, 1, 2, 3), {
        "MAP codes (control)": (GPU / "entry90" / "cover_informative_v", "cover_informative"),
        **{f"weighted, {c}": (HERE / c, "cover_informative") for c in CELLS}})
    tables.show("fleet88, CPU models, cover", "fleet88_seed", (0, 1), {
        "MAP codes (control)": (GPU / "entry86" / "fleet88_cpu_registry", "cover"),
        **{f"weighted, {c}": (HERE / f"fleet88_cpu_{c}", "cover") for c in CELLS}})
    tables.three_draws({
        "MAP codes (control)": (GPU / "entry90" / "severe_cover_informative_v_d{d}", "cover_informative"),
        **{f"weighted, {c}": (HERE / f"severe_{c}_d{{d}}", "cover_informative") for c in CELLS}})


if __name__ == "__main__":
    main()
