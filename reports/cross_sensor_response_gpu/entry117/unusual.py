"""Research log entry 117 (a), exploratory: is a held-out unit's interval excess its distance from the fleet?

Entry 114 found that no linear model of the simulator's recorded unit properties (summaries such as the mean
barometer noise) predicts the unit-common excess. A learnt model errs most where it extrapolates, which a
linear model of the properties cannot see: a unit far from the fleet's centre on either side. This prints,
over fleet88's 88 held-out units, the correlation of the unit-common excess (entry 114's `excess`: the mean
over outputs of log(needed / width), each output centred over units) with

1. each recorded property's squared distance from the fleet: the mean over its entries (per barometer, per
   axis) of z^2, z standardised over the 88 units;
2. the whole unit's: the mean z^2 over all entries, their largest |z|, and a Mahalanobis distance on the
   leading principal components (10 and 20) of the standardised entries;
3. a ridge regression of the excess on the 26 per-property distances, scored leaving each unit out (R^2).

Calibrations: entry 106 (plan alone, with ordinary use), entry 108 (the other session) and entries 110 and 112
(two sessions). From the repository root (data/fleet88 as its README builds it):

    python reports/cross_sensor_response_gpu/entry117/unusual.py --registry data/fleet88
"""

from __future__ import annotations

import argparse
import json
import runpy
from pathlib import Path

import h5py
import numpy as np

G = Path("reports/cross_sensor_response_gpu")
E114 = runpy.run_path(str(G / "entry114/whose_excess.py"))  # excess, corr, ridge_loo_r2
PLAN, USE = E114["PLAN"], E114["USE"]
CALIBRATIONS = {"106 plan": ("entry106/fleet88_cpu_use", PLAN), "106 use": ("entry106/fleet88_cpu_use", USE),
                "108 use": ("entry108/fleet88r_use", USE), "110 use": ("entry110/fleet88r_both", USE),
                "112 use": ("entry112/fleet88r_apart", USE), "112 plan": ("entry112/fleet88r_apart", PLAN)}
RIDGE = (1.0, 10.0, 100.0)


def raw_properties(unit: str, registry: Path) -> dict[str, np.ndarray]:
    """Every numeric property the simulator recorded for the unit, flattened."""
    first = sorted((registry / "runs" / unit).glob("*.h5"))[0]
    with h5py.File(first, "r") as f:
        p = json.loads(f.attrs["simulator"])["unit"]
    return {k: np.ravel(np.asarray(v, float)) for k, v in p.items() if not isinstance(v, str)}


def distances(units: list[str], registry: Path) -> dict[str, np.ndarray]:
    """Per property and for the whole unit: its distance from the 88 units' centre, (units,) each."""
    props = [raw_properties(u, registry) for u in units]
    out: dict[str, np.ndarray] = {}
    columns = []
    for key in props[0]:
        X = np.stack([p[key] for p in props])
        sd = X.std(0)
        keep = sd > 1e-12 * (np.abs(X).max(0) + 1e-300)
        if not keep.any():
            continue
        Z = (X[:, keep] - X[:, keep].mean(0)) / sd[keep]
        out[key] = (Z ** 2).mean(1)
        columns.append(Z)
    Z = np.concatenate(columns, axis=1)
    groups = dict(out)
    out = {"all: mean z^2": (Z ** 2).mean(1), "all: max |z|": np.abs(Z).max(1)}
    U, S, _ = np.linalg.svd(Z - Z.mean(0), full_matrices=False)
    for k in (10, 20):
        out[f"all: Mahalanobis on {k} components"] = ((U[:, :k] * np.sqrt(len(units))) ** 2).sum(1)
    return {**groups, **out}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--registry", type=Path, required=True, help="data/fleet88")
    args = parser.parse_args()
    got = {name: E114["excess"](*where) for name, where in CALIBRATIONS.items()}
    units = sorted(set.intersection(*(set(x) for x in got.values())))
    ys = {name: np.array([got[name][u] for u in units]).mean(1) for name in got}
    dist = distances(units, args.registry)
    names = list(ys)
    print(f"{len(units)} held-out units; the unit-common excess against each distance from the centre")
    print("distance | " + " | ".join(names))
    for key, d in dist.items():
        print(f"{key} | " + " | ".join(f"{E114['corr'](d, ys[n]):+.2f}" for n in names))
    groups = np.stack([d for k, d in dist.items() if not k.startswith("all:")], axis=1)
    print(f"ridge on the {groups.shape[1]} per-property distances, left-out R^2:")
    for n in names:
        fits = ", ".join(f"lambda {lam:g}: {E114['ridge_loo_r2'](groups, ys[n], lam):+.2f}" for lam in RIDGE)
        print(f"   {n}: {fits}")
    every = [abs(E114["corr"](d, ys[n])) for d in dist.values() for n in names]
    print(f"largest |r| over {len(dist)} distances and {len(names)} calibrations: {max(every):.2f}; "
          f"|r| a chance correlation of 88 units exceeds with probability 0.05: "
          f"{1.96 / np.sqrt(len(units) - 3):.2f}")


if __name__ == "__main__":
    main()
