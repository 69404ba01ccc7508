"""The uncertainty report: coverage, width and NLL per method, the per-unit coverage
target, MAPIE's gap, fault-detection AUROC, embedded cost, and figures."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.figures import save_figure, subplots
from anytip.report.markdown import image, table
from anytip.report.writer import Report

BAND = (0.87, 0.93)


def is_target(row: dict[str, Any]) -> bool:
    """Whether a coverage row is a whole target (force, angle, position, ...) rather than one
    output; rows written before targets were named carry the fingertip's two."""
    return row.get("target_group", row["group"] in ("force", "angle"))


def _group(rows: list[dict[str, Any]], *keys: str) -> dict[tuple, list[dict[str, Any]]]:
    out: dict[tuple, list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        out[tuple(r[k] for k in keys)].append(r)
    return out


def coverage_table(rows: list[dict[str, Any]]) -> str:
    """Per nominal level, method and group: coverage over units (min/mean/max), width, NLL."""
    body = []
    sel = [r for r in rows if "nominal_coverage" in r and is_target(r)]
    for (level, method, group), rs in sorted(_group(sel, "nominal_coverage", "method", "group").items()):
        c = [r["coverage"] for r in rs]
        nll = [r["nll"] for r in rs if r["nll"] is not None]
        body.append([level, method, group, min(c), float(np.mean(c)), max(c),
                     float(np.mean([r["interval_width"] for r in rs])),
                     float(np.mean(nll)) if nll else "-"])
    return table(["nominal", "method", "group", "coverage min", "mean", "max",
                  "width (the target's unit)", "NLL"], body)


def target_table(rows: list[dict[str, Any]]) -> str:
    """At nominal 0.9: per method, how many (unit, seed, output) lie in the 0.87-0.93 band."""
    sel = [r for r in rows if r.get("nominal_coverage") == 0.9 and not is_target(r)]
    body = []
    for (method,), rs in sorted(_group(sel, "method").items()):
        c = np.array([r["coverage"] for r in rs])
        inside = (c >= BAND[0]) & (c <= BAND[1])
        sd = [r["coverage_sd"] for r in rs if "coverage_sd" in r]
        patches = [r["test_patches"] for r in rs if "test_patches" in r]
        body.append([method, f"{int(inside.sum())}/{len(c)}", float(c.min()), float(c.max()),
                     f"{np.mean(patches):.0f}" if patches else "-", f"{np.mean(sd):.3f}" if sd else "-",
                     "yes" if inside.all() else "no"])
    return table(["method", "unit-outputs in 0.87-0.93", "min", "max", "test patches",
                  "sd of a unit-output's coverage (patch bootstrap)", "target met"], body)


def bootstrap_table(rows: list[dict[str, Any]]) -> str:
    """Per method and resampling: the spread of an exactly calibrated method's per-unit
    coverage at 0.9, and how many unit-outputs it would put in the band (expected), against
    how many the method itself puts there."""
    sel = [r for r in rows if "bootstrap" in r]
    body = []
    for (method, kind), rs in sorted(_group(sel, "method", "bootstrap").items()):
        obs = np.array([r["observed"] for r in rs])
        inside = int(((obs >= BAND[0]) & (obs <= BAND[1])).sum())
        expected = float(np.sum([1 - r["exact_p_outside"] for r in rs]))
        body.append([method, kind, float(np.mean([r["exact_sd"] for r in rs])),
                     float(np.mean([r["exact_lo"] for r in rs])), float(np.mean([r["exact_hi"] for r in rs])),
                     f"{expected:.1f}/{len(rs)}", f"{inside}/{len(rs)}"])
    return table(["method", "patches drawn again", "sd of coverage", "5% point", "95% point",
                  "exact method: expected in band", "observed in band"], body)


def bootstrap_unit_table(rows: list[dict[str, Any]], method: str = "ensemble+conformal") -> str:
    """Per unit (and seed): test and calibration patches, the bootstrap sd of coverage at
    0.9 (mean over outputs; test patches only, and with calibration), and the observed range."""
    sel = [r for r in rows if "bootstrap" in r and r["method"] == method]
    body = []
    for (unit, seed), rs in sorted(_group(sel, "unit", "seed").items()):
        test = [r for r in rs if r["bootstrap"] == "test"]
        both = [r for r in rs if r["bootstrap"] != "test"]
        obs = [r["observed"] for r in test]
        body.append([unit, seed, test[0]["test_patches"], test[0]["cal_patches"],
                     float(np.mean([r["exact_sd"] for r in test])),
                     float(np.mean([r["exact_sd"] for r in both])),
                     float(np.mean([r["exact_p_outside"] for r in both])), min(obs), max(obs)])
    return table(["unit", "seed", "test patches", "calibration patches", "sd (test)", "sd (test+calibration)",
                  "P(exact method outside band)", "observed min", "observed max"], body)


def detection_table(rows: list[dict[str, Any]]) -> str:
    """Fault x signal: mean AUROC over units (min in brackets), per row and per window."""
    sel = [r for r in rows if "auroc" in r]
    signals = sorted({r["method"] for r in sel})
    keys = list(dict.fromkeys((r["fault"], r["window"]) for r in sel))
    by = _group(sel, "fault", "window", "method")
    body = []
    for f, w in keys:
        cells = []
        for s in signals:
            a = [r["auroc"] for r in by[(f, w, s)]]
            cells.append(f"{np.mean(a):.3f} ({min(a):.3f})" if a else "-")
        body.append([f, w, *cells])
    return table(["fault", "rows per score", *[s.removeprefix("detect:") for s in signals]], body)


def drift_flag_table(rows: list[dict[str, Any]]) -> str:
    """The rest-drift detectors at their calibrated limits: share of test rows flagged, clean
    and faulty (mean over units, min or max in brackets)."""
    sel = [r for r in rows if str(r.get("method")).startswith("detect:rest_drift") and r["window"] == 1]
    body = []
    for (method, fault), rs in _group(sel, "method", "fault").items():
        clean, bad = [r["flagged_clean"] for r in rs], [r["flagged_faulty"] for r in rs]
        body.append([method.removeprefix("detect:"), fault, f"{np.mean(clean):.4f} (max {max(clean):.4f})",
                     f"{np.mean(bad):.3f} (min {min(bad):.3f})"])
    return table(["detector", "fault", "clean rows flagged", "faulty rows flagged"], body)


def cost_table(costs: dict[str, Any], members: int, adapted_members: int = 1,
               adapted_hetero: bool = False) -> str:
    """Parameters and multiply-accumulates per inference on the unit, per method, from
    `anytip.uncertainty.costs.embedded_costs`."""
    base, het, rest = costs["point"], costs["hetero"], costs["rest_drift"]
    d, c = costs["outputs"], costs["inputs"]
    body = [["per-unit MLP (point estimate)", base["params"], base["macs"], "-"],
            ["conformal (constant width)", base["params"], base["macs"], f"+{d} floats per level"],
            ["hetero (beta-NLL head)", het["params"], het["macs"], "+d exp()"],
            ["hetero+conformal", het["params"], het["macs"], f"+{d} floats per level"],
            [f"ensemble ({members} members)", members * het["params"], members * het["macs"],
             f"x{members} flash and time"],
            *([[f"adapted ensemble ({adapted_members} folded shared models)",
                 adapted_members * base["params"], adapted_members * base["macs"],
                 f"x{adapted_members} flash and time, +{d} floats per level"]]
              if adapted_members > 1 else []),
            *([["adapted hetero (folded shared model, beta-NLL head)", het["params"], het["macs"],
                f"+d exp(), +{d} floats per level"]] if adapted_hetero else []),
            ["input novelty (Mahalanobis)", c * (c + 1), c * (c + 1), "-"],
            ["rest drift (rest model, block minima)", rest["parameters"], rest["macs"],
             f"{rest['state']} floats of state"],
            ["flatline (running variance)", 0, 3 * c, f"{2 * c} floats of state"]]
    return table(["method", "parameters", "MACs", "extra"], body)


def calibration_curves(levels: np.ndarray, curves: list[dict[str, list[float]]], path: Path) -> None:
    fig, ax = subplots(figsize=(5.5, 5))
    for name in curves[0]:
        ax.plot(levels, np.mean([c[name] for c in curves], 0), "o-", ms=3, label=name)
    ax.plot([0, 1], [0, 1], "k--", lw=0.8)
    ax.set(xlabel="nominal coverage", ylabel="empirical coverage (held-out patches)",
           title="calibration curves (mean over units and outputs)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save_figure(fig, path)


def coverage_map(angles: np.ndarray, covered: np.ndarray, path: Path, title: str) -> None:
    """Force coverage at nominal 0.9 over the contact region (15-degree cells)."""
    deg = np.degrees(angles)
    t_edges, p_edges = np.arange(-45, 60, 15), np.arange(-135, 60, 15)
    s, _, _ = np.histogram2d(deg[:, 0], deg[:, 1], bins=[t_edges, p_edges], weights=covered)
    n, _, _ = np.histogram2d(deg[:, 0], deg[:, 1], bins=[t_edges, p_edges])
    with np.errstate(invalid="ignore", divide="ignore"):
        cov = s / n
    fig, ax = subplots(figsize=(8, 4.2))
    im = ax.pcolormesh(p_edges, t_edges, cov, shading="flat", cmap="RdYlGn", vmin=0.6, vmax=1.0)
    fig.colorbar(im, ax=ax, label="coverage at nominal 0.9")
    ax.set(xlabel="phi [deg]", ylabel="theta [deg]", title=title, aspect="equal")
    save_figure(fig, path)


def coverage_vs_force(force: np.ndarray, covered: dict[str, np.ndarray], path: Path) -> None:
    edges = np.quantile(force, np.linspace(0, 1, 11))
    which = np.clip(np.digitize(force, edges) - 1, 0, 9)
    centres = [float(np.median(force[which == b])) for b in range(10)]
    fig, ax = subplots(figsize=(6, 4))
    for name, c in covered.items():
        ax.plot(centres, [c[which == b].mean() for b in range(10)], "o-", ms=3, label=name)
    ax.axhspan(*BAND, color="grey", alpha=0.2)
    ax.set(xlabel="|F| [N] (decile medians)", ylabel="force coverage at nominal 0.9",
           title="coverage against contact force")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save_figure(fig, path)


def write_report(ctx: Any, rows: list[dict[str, Any]], fig: dict[str, Any], opts: Any,
                 levels: np.ndarray, costs: dict[str, Any]) -> Path:
    d = ctx.run_dir
    covered = {m: np.concatenate([c[m] for c in fig["covered"]]) for m in fig["covered"][0]}
    calibration_curves(levels, fig["curves"], d / "calibration_curves.png")
    contact_figures = bool(fig["angles"])  # the fingertip's: coverage over its contact region and force
    if contact_figures:
        angles, force = np.concatenate(fig["angles"]), np.concatenate(fig["force"])
        coverage_vs_force(force, covered, d / "coverage_vs_force.png")
        for m in ("conformal", "ensemble+conformal", "ensemble"):
            coverage_map(angles, covered[m], d / f"coverage_map_{m.replace('+', '_')}.png",
                         f"{m}: force coverage at nominal 0.9")
    gap = [abs(r["mapie_minus_own_width"]) for r in rows if "mapie_minus_own_width" in r]
    units = sorted({r["unit"] for r in rows})
    parts = [
        f"# Uncertainty: {ctx.spec.name}\n",
        f"{len(units)} units, seeds {ctx.spec.all_seeds}, {opts.members} ensemble members, "
        f"beta-NLL beta={opts.beta}. Test rows: held-out patches; conformal calibration: a "
        f"further {opts.calib_patch_fraction:.0%} of each unit's other patches, whole.\n",
        "## Coverage, width and NLL (held-out patches)\n", coverage_table(rows),
        "\n## Target: coverage of every unit and output within 0.87-0.93 at nominal 0.9\n",
        target_table(rows),
        f"\nMAPIE (SplitConformalRegressor, prefit, absolute residual) against the own `conformal` "
        f"on the same residuals: largest width difference {max(gap) if gap else float('nan'):.2e}.\n",
        "## Is 0.87-0.93 per unit decidable? Patch bootstrap at nominal 0.9\n",
        "Whole test patches (and, for the second line of each method, whole calibration patches) "
        "drawn again with replacement, 0.9 added to the shift from the observed coverage: where a "
        "method with exactly nominal coverage would land.\n", bootstrap_table(rows),
        "\nPer unit, `ensemble+conformal`:\n", bootstrap_unit_table(rows),
        "\n## Fault detection: AUROC, mean over units (min)\n", detection_table(rows),
        *[f"\n- {line}\n" for line in ctx.provenance.get("skipped", [])],
        "\nRest-drift detectors at their limits (the 99.9% point of the clean calibration "
        "distances; `other_runs`: fitted on the unit's other power-ups):\n",
        drift_flag_table(rows),
        "\n## Embedded cost\n", cost_table(costs, opts.members,
                                             opts.adapted.members if opts.adapted else 1,
                                             bool(opts.adapted and opts.adapted.hetero)),
        "\n## Figures\n", image("calibration_curves.png", "calibration curves"),
        *([image("coverage_vs_force.png", "coverage against force"),
           *[image(f"coverage_map_{m}.png", m) for m in ("conformal", "ensemble_conformal", "ensemble")]]
          if contact_figures else []),
    ]
    return Report(d).add(*parts).write()
