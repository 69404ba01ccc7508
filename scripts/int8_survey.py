"""int8 RMSE increase over float32 for every unit of per-unit model files, on held-out rows.

For each unit (the first model of that unit in the file) the script takes the reference rows
`anytip export` takes: up to --rows in-contact rows of the unit's held-out patches (from the model's
run directory, see `anytip.deploy.held_out`), half to calibrate the int8 rounding and half scored.
It quantizes as the c-int8 export does and scores the numpy int8 model (`quantize.simulate`, equal
to the compiled C on x86) and the float model against the targets.

    .venv/bin/python scripts/int8_survey.py reports/baseline/models/per_unit_seed0 \
        reports/cross_sensor/models/per_unit_seed2 [--rows 20000] [--json out.json]

The registry is the one the run's provenance.json names (or --registry). Prints one line per unit
and the worst increase; units whose rows are not known to be held out are refused.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from anytip.data.registry import Registry
from anytip.deploy.export import prepare, quantize_reference, rmse
from anytip.deploy.held_out import run_dir_of
from anytip.deploy.quantize import simulate
from anytip.errors import AnytipError
from anytip.models.io import load_models


def registry_of(model: Path, given: str | None) -> Registry:
    """--registry, else the registry the model's run recorded in provenance.json."""
    if given:
        return Registry(Path(given), create=False)
    run_dir = run_dir_of(model)
    if run_dir is None:
        raise AnytipError(f"{model} is not inside an experiment run directory; give --registry")
    return Registry(Path(json.loads((run_dir / "provenance.json").read_text())["registry"]), create=False)


def survey_unit(model: Path, unit: str, registry: Registry, rows: int) -> dict:
    """float and int8 RMSE on the unit's scored held-out rows, and the relative increase."""
    t = time.time()
    p = prepare(model, unit, registry, rows)
    if p.ref.held_out is None or p.ref.targets is None:
        raise AnytipError(f"{model} unit {unit}: no held-out registry rows ({p.ref.note})")
    q = quantize_reference(p.net, p.ref, p.y_model)
    ev = p.ref.eval_rows
    f, i8 = rmse(p.y_model[ev], p.ref.targets[ev]), rmse(simulate(q, p.ref.x[ev]), p.ref.targets[ev])
    inc = {k: (i8[k] - f[k]) / f[k] for k in f}
    return {"model": str(model), "unit": unit, "scored_rows": int(ev.sum()),
            "calibration_rows": int(p.ref.cal.sum()), "float": f, "int8": i8, "increase": inc,
            "seconds": round(time.time() - t, 1)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("models", nargs="+", help="per-unit model files or directories inside run directories")
    ap.add_argument("--registry", default=None)
    ap.add_argument("--rows", type=int, default=20000)
    ap.add_argument("--json", default=None, help="write the rows here")
    args = ap.parse_args()
    out = []
    for m in map(Path, args.models):
        reg = registry_of(m, args.registry)
        for unit in dict.fromkeys(load_models(m).meta["unit_ids"]):
            r = survey_unit(m, unit, reg, args.rows)
            out.append(r)
            inc, f = r["increase"], r["float"]
            print(f"{unit:<10} force {inc['force_rmse_n']:+7.2%}  angle {inc['angle_rmse_rad']:+7.2%}  "
                  f"(float {f['force_rmse_n']:.4f} N, {f['angle_rmse_rad']:.5f} rad; "
                  f"{r['scored_rows']} rows, {r['seconds']} s)", flush=True)
    worst = max(out, key=lambda r: max(r["increase"].values()))
    print(f"worst: {worst['unit']} force {worst['increase']['force_rmse_n']:+.2%}, "
          f"angle {worst['increase']['angle_rmse_rad']:+.2%}")
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=2) + "\n")


if __name__ == "__main__":
    main()
