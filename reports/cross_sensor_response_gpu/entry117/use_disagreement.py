"""Research log entry 117 (b), exploratory: does a unit's ordinary use show where its network errs?

A unit calibrated with ordinary use (`anytip calibrate --ordinary-use 600`) reads the pressures of its use,
and the joint fit of its codes gives every such row a contact: the response model's inverse at the unit's
codes. Neither saw the row's label. Where the unit's network (trained on its plan and the transferred rows)
and that inverse disagree on its use rows, one of them errs away from the plan, which the plan's own
residuals (the width of its intervals) cannot show. Entry 114 found the unit-common interval excess is the
unit's own and that no recorded quantity predicts it; this asks whether that disagreement does.

For each held-out unit of fleet88 (entry 106's folds), calibrated as `anytip calibrate` calibrates it with
its fold's run (entry 106: the recipe with 600 s of ordinary use), this records per output:
- `disagree`: the RMS over the use rows the joint fit read of (network - fitted contact);
- `from_start`: the RMS of (network - pooled start network) there (how far the unit's network moved from the
  fleet's);
- `own`: the calibration's own half-width (the plan's in-sample 90% residual quantile).
It writes them to `--out` (JSON, one record per unit) and prints the correlation over units of
log(disagree / own) and log(from_start / own), per output and in their unit-common part (mean over outputs,
each centred over units), with the unit-common excess of entries 106, 108, 110 and 112 (entry 114's
`excess`). From the repository root, one fold per process:

    python reports/cross_sensor_response_gpu/entry117/use_disagreement.py --fold 0 --registry data/fleet88 \
        --out reports/cross_sensor_response_gpu/entry117/fold0.json
    python reports/cross_sensor_response_gpu/entry117/use_disagreement.py --read \
        reports/cross_sensor_response_gpu/entry117/fold{0,1}.json
"""

from __future__ import annotations

import argparse
import json
import runpy
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
import torch

import anytip.calibrate.response as calibrate_module
from anytip.calibrate import calibrate_unit
from anytip.data.registry import Registry
from anytip.models.io import load_models
from anytip.train.metrics import predict

G = Path("reports/cross_sensor_response_gpu")
RUN = G / "entry106/fleet88_cpu_use/fleet88_seed{fold}"
OUTPUTS = ("fx", "fy", "fz", "theta", "phi")


def calibrate_and_read(run: Path, unit: str, registry: Registry) -> dict[str, Any]:
    """One unit calibrated with 600 s of ordinary use; the use rows' fitted contacts, the start network's
    contacts there and the unit's network's, compared per output."""
    seen: dict[str, torch.Tensor] = {}
    inner = calibrate_module.unit_codes_with_use

    def capture(fit, recipe, fleet, X, Y0, *args, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN202
        codes, fitted = inner(fit, recipe, fleet, X, Y0, *args, **kwargs)
        seen.update(X=X.detach().cpu(), Y0=Y0.detach().cpu(), fitted=fitted.detach().cpu())
        return codes, fitted

    calibrate_module.unit_codes_with_use = capture
    try:
        with tempfile.TemporaryDirectory() as out:
            got = calibrate_unit(run, unit, registry, Path(out), budget_seconds=120, method="response",
                                 use_seconds=600, plan_strategy="cover_informative")
            net = load_models(Path(out) / "model.safetensors")
    finally:
        calibrate_module.unit_codes_with_use = inner
    pred = predict(net.model, net.in_scaler, net.out_scaler, seen["X"][None])[0]

    def rms(a: torch.Tensor, b: torch.Tensor) -> list[float]:
        return (a - b).pow(2).mean(0).sqrt().tolist()

    own = got.intervals["own_halfwidth"] if "own_halfwidth" in got.intervals else got.intervals["halfwidth"]
    return {"unit": unit, "use_rows": len(seen["X"]), "disagree": rms(pred, seen["fitted"]),
            "from_start": rms(pred, seen["Y0"]), "own": [own[n] for n in OUTPUTS], "wall_s": got.wall_s}


def run_fold(fold: int, registry: Path, out: Path) -> None:
    """Every held-out unit of entry 106's fold, calibrated with its fold's run, into `out` as it goes."""
    run = Path(str(RUN).format(fold=fold))
    units = json.loads((run / "provenance.json").read_text())["cross_sensor"][f"seed{fold}"]["units"]["test"]
    done = json.loads(out.read_text()) if out.is_file() else []
    have = {r["unit"] for r in done}
    reg = Registry(registry, create=False)
    for unit in units:
        if unit in have:
            continue
        done.append(calibrate_and_read(run, unit, reg))
        out.write_text(json.dumps(done, indent=1))
        print(f"{unit}: disagree {np.round(done[-1]['disagree'], 3)}, own {np.round(done[-1]['own'], 3)}",
              flush=True)


def read(paths: list[Path]) -> None:
    """The correlations the module docstring names."""
    e114 = runpy.run_path(str(G / "entry114/whose_excess.py"))
    records = {r["unit"]: r for p in paths for r in json.loads(p.read_text())}
    calibrations = {"106 use": ("entry106/fleet88_cpu_use", e114["USE"]),
                    "106 plan": ("entry106/fleet88_cpu_use", e114["PLAN"]),
                    "108 use": ("entry108/fleet88r_use", e114["USE"]),
                    "110 use": ("entry110/fleet88r_both", e114["USE"]),
                    "112 use": ("entry112/fleet88r_apart", e114["USE"])}
    excess = {name: e114["excess"](*where) for name, where in calibrations.items()}
    units = sorted(set(records).intersection(*excess.values()))
    rows = np.mean([records[u]["use_rows"] for u in units])
    print(f"{len(units)} held-out units, {rows:.0f} use rows each")
    own = np.log([records[u]["own"] for u in units])
    for signal in ("disagree", "from_start"):
        s = np.log([records[u][signal] for u in units]) - own
        s = s - s.mean(0)
        print(f"log({signal} / own): spread (sd) per output {np.round(s.std(0), 3)}")
        for name, by_unit in excess.items():
            e = np.array([by_unit[u] for u in units])
            per = " ".join(f"{e114['corr'](s[:, d], e[:, d]):+.2f}" for d in range(len(OUTPUTS)))
            print(f"   ~ excess of {name}: common {e114['corr'](s.mean(1), e.mean(1)):+.2f}; {per}")
    print(f"|r| a chance correlation of {len(units)} units exceeds with probability 0.05: "
          f"{1.96 / np.sqrt(len(units) - 3):.2f}")
    ceiling(records, e114)


def ceiling(records: dict[str, dict[str, Any]], e114: dict[str, Any]) -> None:
    """What the disagreement could do at most: each output's held-out width times exp(b (s - mean s)),
    s = log(disagree / own), with b fitted by least squares on the excess of the same held-out units (so
    chosen on the test set: an optimistic bound, not a method); below 0.80 and in the band, before and
    after, in the with-use records of entries 106, 110 and 112 (entry 113's `held_out` and `target`)."""
    e113 = runpy.run_path(str(G / "entry113/analyse.py"))
    print("the ceiling, slope per output fitted on the held-out units themselves (optimistic):")
    for name, sub in (("106", "entry106/fleet88_cpu_use"), ("110", "entry110/fleet88r_both"),
                      ("112", "entry112/fleet88r_apart")):
        rows = [r for k in (0, 1) for r in e113["held_out"](G / sub / f"fleet88_seed{k}", e114["USE"])]
        rows = [r for r in rows if r["unit"] in records]
        w = e113["row_array"](rows, "margin_halfwidth")
        e = np.log(np.sqrt(e113["row_array"](rows, "needed85_halfwidth") *
                           e113["row_array"](rows, "needed95_halfwidth")) / w)
        s = np.log([np.divide(records[r["unit"]]["disagree"], records[r["unit"]]["own"]) for r in rows])
        s, ec = s - s.mean(0), e - e.mean(0)
        b = (s * ec).sum(0) / (s * s).sum(0)
        after = w * np.exp(b * s)
        (n0, band0), (n1, band1) = e113["target"](w, rows), e113["target"](after, rows)
        narrower = np.round((ec - b * s).std(0) / ec.std(0), 3)
        print(f"   {name} with use ({len(rows)} units): slopes {np.round(b, 2)}, excess spread x{narrower}; "
              f"below 0.80 {n0} -> {n1}, in band {band0:.1%} -> {band1:.1%}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fold", type=int, choices=(0, 1))
    parser.add_argument("--registry", type=Path, help="data/fleet88")
    parser.add_argument("--out", type=Path, help="JSON records of the fold's units (resumed where present)")
    parser.add_argument("--read", type=Path, nargs="+", help="read these records instead of calibrating")
    args = parser.parse_args()
    if args.read:
        read(args.read)
    elif args.fold is None or args.registry is None or args.out is None:
        parser.error("give --fold, --registry and --out, or --read")
    else:
        run_fold(args.fold, args.registry, args.out)


if __name__ == "__main__":
    main()
