"""How far a unit's empirical coverage scatters from patch to patch: a patch bootstrap.

Rows within a held-out patch are strongly correlated (one press, one place on the dome), so
a unit's test set holds only as many independent pieces as it has test patches. Resampling
whole patches with replacement gives the sampling spread of its empirical coverage; added
to the nominal level, that is where the empirical coverage of a method whose coverage is
exactly nominal would land. For a conformal method, resampling the calibration patches as
well adds the spread of its quantile.
"""

from __future__ import annotations

import numpy as np

from anytip.uncertainty import conformal as cp


def patch_sums(values: np.ndarray, patch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per patch: sums of values (n, d) and row counts -> (P, d) and (P,), in order of
    np.unique(patch)."""
    _, inv = np.unique(patch, return_inverse=True)
    sums = np.zeros((inv.max() + 1, values.shape[1]))
    np.add.at(sums, inv, values)
    return sums, np.bincount(inv).astype(np.float64)


def bootstrap_test_patches(covered: np.ndarray, patch: np.ndarray, n_boot: int,
                         rng: np.random.Generator) -> np.ndarray:
    """Coverage (n_boot, d) of covered (n, d) bool over test patches drawn with replacement."""
    sums, counts = patch_sums(covered.astype(np.float64), patch)
    draws = rng.multinomial(len(counts), np.full(len(counts), 1 / len(counts)), size=n_boot)  # (B, P)
    return (draws @ sums) / (draws @ counts)[:, None]


def conformal_patch_bootstrap(scores_cal: np.ndarray, patch_cal: np.ndarray, half_scale_t: np.ndarray | None,
                              resid_t: np.ndarray, patch_t: np.ndarray, level: float, n_boot: int,
                              rng: np.random.Generator) -> np.ndarray:
    """Coverage (n_boot, d) of split conformal when both its calibration patches and the
    test patches are drawn again: calibration scores (m, d), test |y - mu| (n, d) and the
    test scale (n, d) or None (absolute residual)."""
    groups = [np.flatnonzero(patch_cal == p) for p in np.unique(patch_cal)]
    test_ids, inv_t = np.unique(patch_t, return_inverse=True)
    out = np.empty((n_boot, resid_t.shape[1]))
    for b in range(n_boot):
        rows = np.concatenate([groups[i] for i in rng.integers(len(groups), size=len(groups))])
        q = cp.conformal_quantile(scores_cal[rows], 1 - level)
        half = q if half_scale_t is None else q * half_scale_t
        covered = (resid_t <= half).astype(np.float64)
        pick = np.bincount(rng.integers(len(test_ids), size=len(test_ids)), minlength=len(test_ids))
        w = pick[inv_t].astype(np.float64)
        out[b] = w @ covered / w.sum()
    return out


def exact_method_band(boot: np.ndarray, observed: np.ndarray, level: float,
                      band: tuple[float, float]) -> dict[str, np.ndarray]:
    """Where an exactly calibrated method would land: level + (boot - observed). Returns per
    output (d,) the bootstrap std, the 5% and 95% points and the chance of leaving `band`."""
    exact = level + (boot - observed)
    outside = (exact < band[0]) | (exact > band[1])
    return {"sd": exact.std(0), "lo": np.quantile(exact, 0.05, axis=0),
            "hi": np.quantile(exact, 0.95, axis=0), "p_outside": outside.mean(0)}
