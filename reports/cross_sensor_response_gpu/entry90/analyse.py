"""Research log entries 90-91's tables: plans chosen for what they tell the codes (`informative`,
`cover_informative`) against `cover`: the validation units' loss per fold and the held-out units
paired per unit, plan alone and with ordinary use; other16 (entry 83's `e60_d0` the control), other16's
severe model (`severe_d0`) and fleet88's CPU models (entry 86's `fleet88_cpu_registry`); and the
diagnostic's residuals of each plan's codes per |F| band. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry90/analyse.py
"""

from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
GPU = HERE.parent
BUDGET = 120.0
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
# (name, runs, fold prefix, folds, arms: {arm: (root, strategy)}), the first arm the control
SETS = (
    ("other16", "other16_seed", (0, 1, 2, 3), {
        "cover (control)": (GPU / "entry83" / "e60_d0", "cover"),
        "informative, d": (HERE / "d", "informative"), "informative, v": (HERE / "v", "informative"),
        "cover_informative, d": (HERE / "cover_informative_d", "cover_informative"),
        "cover_informative, v": (HERE / "cover_informative_v", "cover_informative"),
        "one force level, v": (HERE / "force_cells_v", "cover_informative"),
        "low forces kept, v": (HERE / "keep_low_v", "cover_informative")}),
    ("other16, severe model", "other16_seed", (0, 1, 2, 3), {
        "cover (control)": (GPU / "entry83" / "severe_d0", "cover"),
        "informative, v": (HERE / "severe_v_d0", "informative"),
        "cover_informative, v": (HERE / "severe_cover_informative_v_d0", "cover_informative")}),
    ("fleet88, CPU models", "fleet88_seed", (0, 1), {
        "cover (control)": (GPU / "entry86" / "fleet88_cpu_registry", "cover"),
        "informative, v": (HERE / "fleet88_cpu_v", "informative"),
        "cover_informative, v": (HERE / "fleet88_cpu_cover_informative_v", "cover_informative")}),
    ("fleet88, 1,024-unit models", "fleet88_seed", (0, 1), {
        "cover (control)": (GPU / "entry86" / "fleet88_registry", "cover"),
        "cover_informative, v": (HERE / "fleet88_gpu_cover_informative_v", "cover_informative")}),
)
BANDS = ("0-3", "3-7", "7-13", "13-19", "19+")


def done(root: Path, prefix: str, folds: tuple[int, ...]) -> bool:
    return all((root / f"{prefix}{k}" / "metrics.json").is_file() for k in folds)


def val_losses(root: Path, prefix: str, folds: tuple[int, ...], method: str) -> list[float] | None:
    """The validation units' loss of `method` at 120 s, fold by fold (None: not run)."""
    got = [read_json(root / f"{prefix}{k}" / "provenance.json")["cross_sensor"][f"seed{k}"]["val_loss"]
           .get(method, {}).get("120") for k in folds]
    return None if None in got else got


def per_unit(root: Path, prefix: str, folds: tuple[int, ...], method: str, key: str) -> dict[str, float]:
    """{held-out unit: ratio to its reference} of `method` at 120 s over the folds under root."""
    rows = [r for k in folds for r in read_json(root / f"{prefix}{k}" / "metrics.json")["results"]]
    return unit_ratios(rows, key).get((method, BUDGET), {})


def show(name: str, prefix: str, folds: tuple[int, ...], arms: dict[str, tuple[Path, str]]) -> None:
    arms = {a: arm for a, arm in arms.items() if done(arm[0], prefix, folds)}
    control_root, control = next(iter(arms.values()))
    print(f"\n{name}: validation units' loss at 120 s per fold, mean (alone | with use)")
    for arm, (root, strategy) in arms.items():
        parts = []
        for kind in ("", "+use"):
            got = val_losses(root, prefix, folds, f"response{kind}@{strategy}")
            text = "-" if got is None else f"{' '.join(f'{v:.5f}' for v in got)} mean {np.mean(got):.5f}"
            parts.append(text)
        print(f"  {arm:22s} {parts[0]} | {parts[1]}")
    for kind in ("", "+use"):
        for label, key in KEYS.items():
            base = per_unit(control_root, prefix, folds, f"response{kind}@{control}", key)
            for arm, (root, strategy) in arms.items():
                per = per_unit(root, prefix, folds, f"response{kind}@{strategy}", key)
                if not per:
                    continue
                m, lo, hi = mean_interval(list(per.values()))
                ratios = [per[u] / base[u] for u in base]
                paired = "" if root == control_root else f" paired x{paired_text(ratios)}"
                print(f"  response{kind} {label} {arm:22s} {m:.3f}x [{lo:.2f}, {hi:.2f}]{paired}")


def residual_table() -> None:
    """The diagnostic: RMS residual (Pa) of each plan's codes per |F| band, averaged over units and folds."""
    for arm in ("d", "v", "cover_informative_v"):
        files = sorted((HERE / "code_residuals" / arm).glob("other16_seed*/code_residuals.json"))
        if not files:
            continue
        got = [read_json(f) for f in files]
        print(f"\ncodes' residual, {arm}, {len(files)} folds; |F| bands {', '.join(BANDS)} "
              "N; share of presses under 7 N")
        for plan in [p for p in got[0]["rms_pa"] if p != "oracle"] + ["oracle"]:
            rms = [v for g in got for v in g["rms_pa"][plan].values()]
            forces = [f for g in got for f in g.get("press_mean_force_n", {}).get(plan, {}).values()]
            low = [np.mean(np.array(f) < 7) for f in forces]
            share = f"{np.mean(low):.0%}" if low else "-"
            print(f"  {plan:12s} " + " ".join(f"{v:6.0f}" for v in np.nanmean(rms, 0)) + f"   {share}")


DRAWS = (0, 1, 2)
SEVERE = {"cover (control)": (GPU / "entry83" / "severe_d{d}", "cover"),
          "cover_informative, v": (HERE / "severe_cover_informative_v_d{d}", "cover_informative"),
          "low forces kept, v": (HERE / "severe_keep_low_v_d{d}", "cover_informative")}


def three_draws(arms: dict[str, tuple[Path, str]] = SEVERE) -> None:
    """other16's severe model over three draws of the start network, as entry 83 reported its headline:
    each held-out unit's RMSE averaged over the draws (`unit_ratios` pools them as seeds), then paired
    against `arms`' first, the control (roots with `{d}` for the draw)."""
    roots = {arm: [Path(str(root).format(d=d)) for d in DRAWS] for arm, (root, _) in arms.items()}
    roots = {arm: rs for arm, rs in roots.items() if all(done(r, "other16_seed", (0, 1, 2, 3)) for r in rs)}
    if len(roots) < 2:
        return
    print("\nother16, severe model, three draws of the start network: validation loss (mean over draws and "
          "folds, alone | with use), held-out units")
    for arm in roots:
        strategy = arms[arm][1]
        alone, use = ([v for r in roots[arm] for v in val_losses(r, "other16_seed", (0, 1, 2, 3),
                                                                 f"response{kind}@{strategy}")]
                      for kind in ("", "+use"))
        print(f"  {arm:22s} {np.mean(alone):.5f} | {np.mean(use):.5f}")
    for kind in ("", "+use"):
        for label, key in KEYS.items():
            per = {}
            for arm in roots:
                strategy = arms[arm][1]
                rows = [x for r in roots[arm] for k in (0, 1, 2, 3)
                        for x in read_json(r / f"other16_seed{k}" / "metrics.json")["results"]]
                per[arm] = unit_ratios(rows, key)[(f"response{kind}@{strategy}", BUDGET)]
            base = per[next(iter(roots))]
            for arm, got in per.items():
                m, lo, hi = mean_interval(list(got.values()))
                paired = "" if got is base else f" paired x{paired_text([got[u] / base[u] for u in base])}"
                print(f"  response{kind} {label} {arm:22s} {m:.3f}x [{lo:.2f}, {hi:.2f}]{paired}")


def against_cells() -> None:
    """Entries 92-93: each variant of the exchanges paired per held-out unit against entry 91's cells."""
    folds, theirs = (0, 1, 2, 3), HERE / "cover_informative_v"
    for entry, name in (("92", "force_cells_v"), ("93", "keep_low_v")):
        mine = HERE / name
        if not done(mine, "other16_seed", folds):
            continue
        print(f"\nentry {entry} ({name}) against entry 91's cells, paired per held-out unit")
        for kind in ("", "+use"):
            for label, key in KEYS.items():
                a = per_unit(mine, "other16_seed", folds, f"response{kind}@cover_informative", key)
                b = per_unit(theirs, "other16_seed", folds, f"response{kind}@cover_informative", key)
                print(f"  response{kind} {label} x{paired_text([a[u] / b[u] for u in b])}")


def main() -> None:
    for name, prefix, folds, arms in SETS:
        show(name, prefix, folds, arms)
    against_cells()
    three_draws()
    residual_table()


if __name__ == "__main__":
    main()
