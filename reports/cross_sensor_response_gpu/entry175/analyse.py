"""Research log entry 175's reading of logs/step_cost.log (`run.sh`): rule 1, each compiled variant's
gradients within float32 rounding of `mse_grads`'; rule 2, the seconds a compiled step would save in a
calibration of STEPS steps against its first call's; rule 3, the products' share of the step and the best
variant's ratio.

    python reports/cross_sensor_response_gpu/entry175/analyse.py > \
        reports/cross_sensor_response_gpu/entry175/logs/analyse.log
"""

from __future__ import annotations

from pathlib import Path

LOG = Path(__file__).parent / "logs" / "step_cost.log"
STEPS = 19_600  # the unit network's training steps in one `anytip calibrate` at 120 s (entry 172)
GATE, PRODUCTS_SHARE, CALLS_RATIO = 1e-5, 0.60, 0.80


def read() -> tuple[list[tuple[float, float]], list[dict]]:
    """(products_us, step_us) per products line; one dict per variant line (state, variant, the numbers)."""
    products, variants = [], []
    for line in LOG.read_text().splitlines():
        w = line.split()
        if w and w[0] == "products":
            products.append((float(w[w.index("products_us") + 1]), float(w[w.index("step_us") + 1])))
        elif len(w) > 2 and w[1] == "variant":
            pairs = dict(zip(w[3::2], map(float, w[4::2]), strict=True))
            variants.append({"state": w[0], "variant": w[2], **pairs})
    return products, variants


def main() -> None:
    products, variants = read()
    bad = [f"{v['state']} {v['variant']}" for v in variants if v["grad_rel_diff"] >= GATE]
    print(f"rule 1: {len(variants) - len(bad)} of {len(variants)} variant runs within {GATE:g} of mse_grads'"
          + (f"; NOT READ: {', '.join(bad)}" if bad else ""))
    print(f"\nrule 2, a calibration of {STEPS:,} steps")
    print("| variant | cache | first call (s) | compiled step (us) | eager step (us) | compiled / eager "
          "| steps' seconds saved | saved less the first call (s) |")
    print("|---|---|---|---|---|---|---|---|")
    for v in variants:
        if f"{v['state']} {v['variant']}" in bad:
            continue
        saved = (v["eager_us"] - v["compiled_us"]) * STEPS / 1e6
        print(f"| {v['variant']} | {v['state']} | {v['first_call_s']:.2f} | {v['compiled_us']:.1f} | "
              f"{v['eager_us']:.1f} | x{v['ratio']:.3f} | {saved:.2f} | {saved - v['first_call_s']:+.2f} |")
    warm = [v for v in variants if v["state"] == "warm" and f"warm {v['variant']}" not in bad]
    gains = [v["variant"] for v in warm
             if (v["eager_us"] - v["compiled_us"]) * STEPS / 1e6 > v["first_call_s"]]
    print(f"warm variants that save time in a calibration: {', '.join(gains) or 'none'}")
    shares = [p / s for p, s in products]
    share = sum(shares) / len(shares)
    best = min(v["ratio"] for v in variants if f"{v['state']} {v['variant']}" not in bad)
    readings = ", ".join(f"{p:.1f}/{s:.1f} us" for p, s in products)
    print(f"\nrule 3: the products' sum over the step {readings} "
          f"({', '.join(f'{x:.0%}' for x in shares)}; mean {share:.0%}); the best variant's step x{best:.3f}")
    if best < CALLS_RATIO:
        print("H-calls: a compiled step under 0.8 of eager's")
    elif share >= PRODUCTS_SHARE:
        print("H-products: the products at least 60% of the step and no variant under 0.8")
    else:
        print(f"neither: no variant under {CALLS_RATIO:g} of eager's, and the products under "
              f"{PRODUCTS_SHARE:.0%} of the step")


if __name__ == "__main__":
    main()
