"""Research log entry 114 (a), exploratory: whose is a held-out unit's interval excess?

The excess of a unit-output is log(needed / width): the half-width its test rows needed at 0.90 (the
geometric mean of those at 0.85 and 0.95) over the one it was given (the fleet factor times the margin),
after each output's mean over units; its unit-common part is the mean over the five outputs. On fleet88's 88
held-out units this prints:

1. the common part's correlation over units between calibrations: entry 50 (`cover`, the GPU's 1,040-unit
   response models), entry 106 (`cover_informative`, the CPU's 128-unit models; plan alone and with
   ordinary use) and entry 108 (entry 106's calibrations tested in the other session);
2. the place of each unit's test cells (as `shared_split.prepare_seed` draws them for the run's recorded
   roles, checked against the recorded test-row count): a fleet map of how hard a cell is (the pooled start
   network's mean squared error there over the fold's other held-out units) and the unit's own (its errors
   there), each as the log RMS ratio of its test cells to its other cells, against the excess (needs the
   registry: --registry);
3. the simulator's recorded unit properties (from each unit's first run file): each one's correlation with
   the common part, and a ridge regression on all of them scored leaving each unit out (R^2);
4. a signal known before the test: the with-use network's half-width on the plan's rows over the plan-alone
   network's (both in-sample), against each method's excess, in entries 106, 108 and 110-112.

From the repository root (data/fleet88 as its README builds it):

    python reports/cross_sensor_response_gpu/entry114/whose_excess.py --registry data/fleet88
"""

from __future__ import annotations

import argparse
import json
import runpy
from pathlib import Path
from typing import Any

import h5py
import numpy as np

import anytip.train.shared_split as shared_split
from anytip.data.splits import UnitSplit
from anytip.models.io import load_models
from anytip.pipelines.cross_sensor import prepare
from anytip.train.shared_split import main_rows, predict_rows, unit_main_rows

G = Path("reports/cross_sensor_response_gpu")
E113 = runpy.run_path(str(G / "entry113/analyse.py"))  # held_out, row_array, OUTPUTS
FOLD_OF = runpy.run_path(str(G / "entry98/more_val.py"))["fold_of"]
OUTPUTS = E113["OUTPUTS"]
PLAN, USE = "response@cover_informative", "response+use@cover_informative"
CALIBRATIONS = {"50 cover, plan": ("entry50", "response@cover"),
                "50 cover, use": ("entry50", "response+use@cover"),
                "106 cover_informative, plan": ("entry106/fleet88_cpu_use", PLAN),
                "106 cover_informative, use": ("entry106/fleet88_cpu_use", USE),
                "108 the other session, use": ("entry108/fleet88r_use", USE)}
RIDGE = (1.0, 10.0, 100.0)


def row_excess(rows: list[dict[str, Any]]) -> np.ndarray:
    """(units, outputs): each held-out row's excess, after each output's mean over the rows."""
    at = E113["row_array"]
    e = np.log(np.sqrt(at(rows, "needed85_halfwidth") * at(rows, "needed95_halfwidth"))
               / at(rows, "margin_halfwidth"))
    return e - e.mean(0)


def excess(sub: str, method: str) -> dict[str, np.ndarray]:
    """Each held-out unit's excess per output (5,), after each output's mean over units."""
    rows = [r for k in (0, 1) for r in E113["held_out"](G / sub / f"fleet88_seed{k}", method)]
    return {r["unit"]: v for r, v in zip(rows, row_excess(rows), strict=True)}


def corr(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.corrcoef(a, b)[0, 1])


def across_calibrations() -> dict[str, dict[str, np.ndarray]]:
    """Rule 1; returns every calibration's excess by unit."""
    got = {name: excess(*where) for name, where in CALIBRATIONS.items()}
    units = sorted(set.intersection(*(set(x) for x in got.values())))
    print(f"1. the unit-common excess between calibrations, over {len(units)} units (per output after ';')")
    names = list(got)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            ea, eb = (np.array([got[n][u] for u in units]) for n in (a, b))
            per = " ".join(f"{corr(ea[:, d], eb[:, d]):+.2f}" for d in range(len(OUTPUTS)))
            print(f"   {a} ~ {b}: {corr(ea.mean(1), eb.mean(1)):+.2f}; {per}")
    return got


def place_ratios(registry: Path) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Rule 2's maps: per held-out unit, log RMS ratio (5,) of its test cells to its other cells, in the
    fleet map and in its own errors, for entry 106's folds."""
    fleet, own_map = {}, {}
    for k in (0, 1):
        run = G / CALIBRATIONS["106 cover_informative, plan"][0] / f"fleet88_seed{k}"
        ctx, opts, arrays, seed, was = FOLD_OF(run, registry, Path("build/entry114_place"), [])
        split = UnitSplit(*(tuple(was.get(role, ())) for role in ("train", "val", "test", "factor")))
        shared_split.split_units = lambda *_, s=split, **__: s  # the run's recorded roles
        evals = prepare(ctx, arrays, opts, seed).evals  # each unit's test cells as the run drew them
        main = main_rows(arrays, opts.calibration_protocol)
        recorded = {r["unit"]: r["interval_test_rows"] for r in E113["held_out"](run, PLAN)}
        pooled = load_models(run / "models" / f"response_seed{seed}_start.safetensors")
        units = list(was["test"])
        sse = np.zeros((len(units), int(arrays.patch.max()) + 1, len(OUTPUTS)))
        count = np.zeros(sse.shape[:2])
        cells = {}
        for j, u in enumerate(units):
            own = unit_main_rows(arrays, u, main)
            if len(evals[u].test_rows) != recorded[u]:
                raise SystemExit(f"{u}: {len(evals[u].test_rows)} test rows rebuilt, {recorded[u]} recorded")
            cells[u] = evals[u].test_cells
            pred = predict_rows(pooled.model, pooled.in_scaler, pooled.out_scaler, arrays, [own])[0]
            np.add.at(sse[j], arrays.patch[own], (pred - arrays.labels[own]) ** 2)
            np.add.at(count[j], arrays.patch[own], 1)
        for j, u in enumerate(units):
            others = np.delete(np.arange(len(units)), j)
            fleet_mse = sse[others].sum(0) / np.maximum(count[others].sum(0), 1)[:, None]
            own_mse = sse[j] / np.maximum(count[j], 1)[:, None]
            seen = np.flatnonzero(count[j] > 0)
            test, rest = np.intersect1d(seen, cells[u]), np.setdiff1d(seen, cells[u])
            fleet[u] = 0.5 * np.log(fleet_mse[test].mean(0) / fleet_mse[rest].mean(0))
            own_map[u] = 0.5 * np.log(own_mse[test].mean(0) / own_mse[rest].mean(0))
    return fleet, own_map


def by_place(got: dict[str, dict[str, np.ndarray]], registry: Path) -> None:
    """Rule 2."""
    fleet, own_map = place_ratios(registry)
    print("2. the place of the test cells (all 88 units' test-row counts rebuilt as recorded)")
    for label, ratio in (("fleet map", fleet), ("the unit's own errors", own_map)):
        x = np.array([ratio[u] for u in sorted(ratio)])
        print(f"   {label}: spread (sd) per output {' '.join(f'{v:.3f}' for v in x.std(0))}")
        for name in ("106 cover_informative, plan", "106 cover_informative, use"):
            e = np.array([got[name][u] for u in sorted(ratio)])
            per = " ".join(f"{corr(x[:, d], e[:, d]):+.2f}" for d in range(len(OUTPUTS)))
            print(f"      ~ excess of {name}: common {corr(x.mean(1), e.mean(1)):+.2f}; {per}")
    spread = np.array([got["106 cover_informative, use"][u] for u in sorted(fleet)]).std(0)
    print(f"   the excess's spread (sd) per output, 106 with use: {' '.join(f'{v:.3f}' for v in spread)}")


def properties(unit: str, registry: Path) -> dict[str, float]:
    """Summaries of the unit's recorded simulator properties."""
    first = sorted((registry / "runs" / unit).glob("*.h5"))[0]
    with h5py.File(first, "r") as f:
        p: dict[str, Any] = json.loads(f.attrs["simulator"])["unit"]

    def arr(key: str) -> np.ndarray:
        return np.asarray(p[key], float)

    return {"hysteresis": p["hysteresis"], "relax fraction": p["relax_fraction"],
            "relax tau": p["relax_tau_s"], "log modulus": float(np.log(p["modulus_pa"])),
            "shift compliance": p["shift_compliance_m_per_n"],
            "|tc offset|": float(np.abs(arr("tc_offset_pa_per_c")).mean()),
            "tc offset sd": float(arr("tc_offset_pa_per_c").std()),
            "|tc gain|": float(np.abs(arr("tc_gain_per_c")).mean()),
            "log noise": float(np.log(arr("noise_pa")).mean()),
            "gain spread": float(arr("channel_gain").std() / arr("channel_gain").mean()),
            "|direction defect|": float(np.linalg.norm(arr("direction_defect"), axis=1).mean()),
            "preload": float(arr("preload_pa").mean()),
            "temp offset sd": float(arr("temp_sensor_offset_c").std()),
            "bubbles": float(arr("bubble_strength").sum()),
            "log full scale": float(np.log(arr("full_scale_pa")).mean())}


def ridge_loo_r2(X: np.ndarray, y: np.ndarray, lam: float) -> float:
    """R^2 of a ridge regression (standardised X) scored leaving each row out."""
    pred = np.empty_like(y)
    for i in range(len(y)):
        keep = np.arange(len(y)) != i
        mu, sd = X[keep].mean(0), X[keep].std(0)
        Z = (X[keep] - mu) / sd
        beta = np.linalg.solve(Z.T @ Z + lam * np.eye(X.shape[1]), Z.T @ (y[keep] - y[keep].mean()))
        pred[i] = y[keep].mean() + ((X[i] - mu) / sd) @ beta
    return float(1 - ((y - pred) ** 2).sum() / ((y - y.mean()) ** 2).sum())


def by_properties(got: dict[str, dict[str, np.ndarray]], registry: Path) -> None:
    """Rule 3."""
    units = sorted(got["106 cover_informative, use"])
    props = [properties(u, registry) for u in units]
    keys = list(props[0])
    X = np.array([[p[k] for k in keys] for p in props])
    print("3. the simulator's unit properties against the unit-common excess")
    for name in ("106 cover_informative, plan", "106 cover_informative, use"):
        y = np.array([got[name][u] for u in units]).mean(1)
        cells = ", ".join(f"{k} {corr(X[:, i], y):+.2f}" for i, k in enumerate(keys))
        fits = ", ".join(f"lambda {lam:g}: {ridge_loo_r2(X, y, lam):+.2f}" for lam in RIDGE)
        print(f"   {name}: {cells}\n      ridge on all, left-out R^2: {fits}")


TWO_METHODS = {"106": "entry106/fleet88_cpu_use", "108": "entry108/fleet88r_use",
               "110": "entry110/fleet88r_both", "111": "entry111", "112": "entry112/fleet88r_apart"}


def with_use_over_alone() -> None:
    """Rule 4."""
    at = E113["row_array"]
    print("4. log(with-use own / plan-alone own half-width) against the excess: common part; per output")
    for name, sub in TWO_METHODS.items():
        runs = [G / sub / (f"fleet88x_seed{k}" if name == "111" else f"fleet88_seed{k}") for k in (0, 1)]
        by = {m: {r["unit"]: r for run in runs for r in E113["held_out"](run, m)} for m in (PLAN, USE)}
        units = sorted(by[PLAN])
        rows = {m: [by[m][u] for u in units] for m in by}
        signal = np.log(at(rows[USE], "halfwidth") / at(rows[PLAN], "halfwidth"))
        for m, label in ((PLAN, "plan alone"), (USE, "with use")):
            e = row_excess(rows[m])
            per = " ".join(f"{corr(signal[:, d], e[:, d]):+.2f}" for d in range(len(OUTPUTS)))
            print(f"   {name} {label}: {corr(signal.mean(1), e.mean(1)):+.2f}; {per}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--registry", type=Path, required=True, help="fleet88 (its runs and unit properties)")
    args = parser.parse_args()
    got = across_calibrations()
    by_place(got, args.registry)
    by_properties(got, args.registry)
    with_use_over_alone()


if __name__ == "__main__":
    main()
