"""Research log entries 94-95's tables: each transferred row's codes drawn from their Laplace posterior
(`options.response.code_draw_scale` S), and codes fitted with each press's own offset (entry 95), against
the MAP codes: the validation units' loss per fold and the held-out units paired per unit, with entry 90's
tables (`entry90/analyse.py`). Controls: entry 91's `cover_informative_v` cells (other16), its severe
model's three draws, and entry 86's `fleet88_cpu_registry` (fleet88's CPU models, `cover`).
Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry94/analyse.py
"""

import importlib.util
from pathlib import Path

HERE = Path(__file__).parent
GPU = HERE.parent
SCALES = (1, 4)


def entry90():
    """entry90/analyse.py as a module (its tables' code)."""
    spec = importlib.util.spec_from_file_location("entry90_analyse", GPU / "entry90" / "analyse.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main() -> None:
    tables = entry90()
    cells = (GPU / "entry90" / "cover_informative_v", "cover_informative")
    tables.show("other16, default-spread models", "other16_seed", (0, 1, 2, 3), {
        "MAP codes (control)": cells,
        **{f"drawn, scale {s}": (HERE / f"scale{s}", "cover_informative") for s in SCALES},
        "press offsets (95)": (HERE / "offsets", "cover_informative")})
    tables.show("fleet88, CPU models, cover", "fleet88_seed", (0, 1), {
        "MAP codes (control)": (GPU / "entry86" / "fleet88_cpu_registry", "cover"),
        **{f"drawn, scale {s}": (HERE / f"fleet88_cpu_scale{s}", "cover") for s in SCALES}})
    tables.three_draws({
        "MAP codes (control)": (GPU / "entry90" / "severe_cover_informative_v_d{d}", "cover_informative"),
        "cover, MAP codes": (GPU / "entry83" / "severe_d{d}", "cover"),
        **{f"drawn, scale {s}": (HERE / f"severe_scale{s}_d{{d}}", "cover_informative") for s in SCALES},
        "press offsets (95)": (HERE / "severe_offsets_d{d}", "cover_informative")})


if __name__ == "__main__":
    main()
