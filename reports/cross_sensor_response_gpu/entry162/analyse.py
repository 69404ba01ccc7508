"""Research log entry 162's reading: the 64 fresh units SIM25-000 to 063 under each of other16's four folds,
at 120 s, `cover_informative`, the plan alone, against each (unit, fold)'s own per-unit reference. Rule 1:
every unit has a row and a reference under every fold, on as many test rows. Rule 2: each fold's mean over
the same 64 units beside its mean over its own 32 (entry 159); the variance of log r(u, k) between folds,
units and left over. Rule 3: fold 3 over fold 1 per unit. Rule 4: the mean over the four folds and the 64
units, with an interval that resamples both. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry162/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np
from scipy import stats

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
E159 = runpy.run_path(str(HERE.parent / "entry159" / "analyse.py"))
KEYS, ACROSS, FOLDS = E159["KEYS"], E159["ACROSS"], range(4)
UNITS = [f"SIM25-{i:03d}" for i in range(64)]
OWN = {0: 0, 1: 32}  # fold -> the first of its own 32 units among the 64 (entries 158-159)
BUDGET, N_BOOT = 120.0, 10_000


def fold_rows(k: int, from_: int, own: str = "entry158", new: Path = HERE) -> list[dict]:
    """Fold k's rows and references of the 32 units from `from_` on: a fold's own units' rows from entry `own`
    (entry 158's here) and references from entry 159; the other units' rows from `new` (this entry's
    directory here) and references from this entry."""
    if OWN.get(k) == from_:
        rows_at, refs_at = (HERE.parent / e / f"other16f_seed{k}" for e in (own, "entry159"))
    else:
        rows_at, refs_at = new / f"other16f_seed{k}_from{from_}", HERE / f"other16f_seed{k}_from{from_}"
    got = read_json(rows_at / "rows.json")
    rows = [{**r, "seed": got["seed"]} for r in got["rows"] if r["unit"] in UNITS]
    return rows + [r for r in read_json(refs_at / "references.json")["rows"] if r["unit"] in UNITS]


def gate(rows: list[dict], method: str = ACROSS) -> list[str]:
    """Rule 1: the (unit, fold) cells with no row of `method`, no reference, or a reference on other test
    rows."""
    tested = {(r["unit"], r["seed"]): r["test_rows"] for r in rows if r["method"] == "per_unit"}
    scored = {(r["unit"], r["seed"]): r["interval_test_rows"] for r in rows
              if r["method"] == method and r.get("budget_s") == BUDGET}
    cells = [(u, k) for u in UNITS for k in FOLDS]
    return [f"{u} fold {k}" for u, k in cells if (u, k) not in scored or scored[u, k] != tested.get((u, k))]


def ratios(rows: list[dict], method: str = ACROSS) -> dict[str, np.ndarray]:
    """target -> r(u, k), 64 units by 4 folds: the unit's RMSE under fold k over its reference's under
    fold k."""
    out = {}
    for name, key in KEYS.items():
        by_fold = [unit_ratios([r for r in rows if r["seed"] == k], key)[method, BUDGET] for k in FOLDS]
        out[name] = np.array([[by_fold[k][u] for k in FOLDS] for u in UNITS])
    return out


def left_over(x: np.ndarray) -> float:
    """The variance of a units-by-folds table left over after its unit and fold means (two-way, one cell
    each)."""
    res = x - x.mean(0)[None, :] - x.mean(1)[:, None] + x.mean()
    return float((res ** 2).sum() / ((x.shape[0] - 1) * (x.shape[1] - 1)))


def log_rmse(rows: list[dict], method: str, key: str) -> np.ndarray:
    """64 units by 4 folds: log of `key` of `method`'s row (at 120 s; a reference has no budget)."""
    rmse = {(r["unit"], r["seed"]): r[key] for r in rows
            if r["method"] == method and (method == "per_unit" or r.get("budget_s") == BUDGET)}
    return np.log([[rmse[u, k] for k in FOLDS] for u in UNITS])


def exploratory(rows: list[dict], method: str = ACROSS) -> None:
    """After the rules, not written down before: the left-over variance of log RMSE of the method and of the
    reference, and the report's own ratio (each unit's RMSEs averaged over its folds first)."""
    print("\nexploratory, after the rules")
    for name, key in KEYS.items():
        logs = {m: log_rmse(rows, m, key) for m in (method, "per_unit")}
        both = left_over(logs[method] - logs["per_unit"])
        print(f"{name}: left-over variance of log RMSE, the method {left_over(logs[method]):.4f}, the "
              f"reference {left_over(logs['per_unit']):.4f}, their ratio {both:.4f}; the report's ratio, "
              "each unit's RMSEs averaged over its four folds first: "
              + "{:.3f}x [{:.2f}, {:.2f}]".format(*mean_interval(list(unit_ratios(rows, key)[method, BUDGET]
                                                                        .values()))))


def variance_shares(r: np.ndarray) -> dict[str, float]:
    """Two-way (units by folds, one cell each) variance components of log r, as shares of their sum."""
    x = np.log(r)
    n_u, n_k = x.shape
    ms_res = left_over(x)
    comp = {"folds": max((n_u * x.mean(0).var(ddof=1) - ms_res) / n_u, 0.0),
            "units": max((n_k * x.mean(1).var(ddof=1) - ms_res) / n_k, 0.0), "left over": ms_res}
    return {name: v / sum(comp.values()) for name, v in comp.items()}


def crossed_interval(r: np.ndarray) -> tuple[float, float, float]:
    """The mean of r over units and folds, with a 95% interval from resampling units and folds alike."""
    rng = np.random.default_rng(0)
    u = rng.integers(0, r.shape[0], (N_BOOT, r.shape[0]))
    k = rng.integers(0, r.shape[1], (N_BOOT, r.shape[1]))
    boot = np.array([r[np.ix_(uu, kk)].mean() for uu, kk in zip(u, k, strict=True)])
    lo, hi = np.percentile(boot, [2.5, 97.5])
    return float(r.mean()), float(lo), float(hi)


def t_interval(means: np.ndarray) -> tuple[float, float, float]:
    """The mean of the fold means with its 95% t-interval over folds."""
    half = stats.t.ppf(0.975, len(means) - 1) * means.std(ddof=1) / np.sqrt(len(means))
    return float(means.mean()), float(means.mean() - half), float(means.mean() + half)


def main() -> None:
    rows = [r for k in FOLDS for from_ in (0, 32) for r in fold_rows(k, from_)]
    missing = gate(rows)
    print(f"rule 1: {len(UNITS) * len(FOLDS) - len(missing)} of {len(UNITS) * len(FOLDS)} (unit, fold) cells "
          f"with a row and a reference on as many test rows" + (f"; MISSING {missing}" if missing else ""))
    if missing:
        return
    r = ratios(rows)
    text = "{:.3f}x [{:.2f}, {:.2f}]".format
    own = E159["cells"]  # each fold's mean over its own 32 units, entry 159's way
    print("\nrule 2, RMSE over the unit's own reference under the fold, mean over units [95% interval]")
    print("| fold | force, the same 64 units | angle, the same 64 units | force, its own 32 units "
          "(entry 159) |")
    print("|---|---|---|---|")
    for k in FOLDS:
        mine = own([x for x in E159["fresh_rows"]() if x["seed"] == k])[ACROSS, BUDGET, "force"]
        cells = [text(*mean_interval(list(r[n][:, k]))) for n in KEYS]
        print(f"| {k} | " + " | ".join(cells) + f" | {text(*mine)} |")
    for name in KEYS:
        shares = ", ".join(f"{part} {v:.0%}" for part, v in variance_shares(r[name]).items())
        print(f"{name}: variance of log r between {shares}")
    paired = {n: paired_text(list(r[n][:, 3] / r[n][:, 1])) for n in KEYS}
    print(f"\nrule 3: fold 3 over fold 1, per unit, force x{paired['force']}, angle x{paired['angle']}")
    print("\nrule 4, the mean over four folds and 64 units")
    for name in KEYS:
        print(f"{name}: {text(*crossed_interval(r[name]))} resampling units and folds; "
              f"t over the four fold means {text(*t_interval(r[name].mean(0)))}; "
              f"over units alone {text(*mean_interval(list(r[name].mean(1))))}")
    exploratory(rows)


if __name__ == "__main__":
    main()
