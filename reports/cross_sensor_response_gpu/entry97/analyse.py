"""Research log entry 97's reading: fleet88's CPU models with `cover` and `cover_informative` plans rescored
in one run per fold; the validation units' means per fold (against entries 86 and 91), the margin between the
two plans paired unit by unit (`report.cross_sensor.choice_margins`, as the report computes it), each
validation unit's loss under both, and the held-out units paired per unit. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry97/analyse.py
"""

from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import choice_margins, mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json
from anytip.train.label_free import data_family

HERE = Path(__file__).parent
RUNS = [HERE / "fleet88_cpu" / f"fleet88_seed{k}" for k in (0, 1)]
PLANS = ("response@cover", "response@cover_informative")
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}


def main() -> None:
    records = {f"seed{k}": read_json(r / "provenance.json")["cross_sensor"][f"seed{k}"]
               for k, r in enumerate(RUNS)}
    val = {s: r["val_loss"] for s, r in records.items()}
    units = {s: r["val_loss_units"] for s, r in records.items()}
    for plan in PLANS:
        got = [val[s][plan]["120"] for s in val]
        folds = " ".join(f"{v:.5f}" for v in got)
        print(f"{plan}: validation loss per fold {folds}, mean {np.mean(got):.5f}")
    for s in units:
        a, b = (units[s][p]["120"] for p in PLANS)
        print(f"{s}: " + ", ".join(f"{u} {a[u]:.5f} / {b[u]:.5f} (x{b[u] / a[u]:.3f})" for u in a))
    for key, m in choice_margins(val, data_family, units).items():
        interval = f"[{100 * m.lower:+.1f}, {100 * m.upper:+.1f}]%"
        print(f"{key}: best {m.method}, runner-up {m.runner_up}, margin {100 * m.margin:+.1f}%, "
              f"95% interval over {m.n} {m.over} {interval}: {m.verdict}")
    rows = [x for r in RUNS for x in read_json(r / "metrics.json")["results"]]
    for label, key in KEYS.items():
        per = unit_ratios(rows, key)
        a, b = (per[(p, 120.0)] for p in PLANS)
        for plan, got in zip(PLANS, (a, b), strict=True):
            m, lo, hi = mean_interval(list(got.values()))
            print(f"held out {label} {plan}: {m:.3f}x [{lo:.2f}, {hi:.2f}]")
        print(f"  paired, cover_informative over cover: x{paired_text([b[u] / a[u] for u in a])}")


def other16() -> None:
    """The second part: other16's severe model, three start draws, both plans in one run per fold; each
    (draw, validation unit) a pair."""
    runs = {f"d{d}/seed{k}": HERE / f"other16_severe_d{d}" / f"other16_seed{k}"
            for d in (0, 1, 2) for k in range(4)}
    if not all((r / "metrics.json").is_file() for r in runs.values()):
        return
    records = {key: read_json(r / "provenance.json")["cross_sensor"][key.split("/")[1]]
               for key, r in runs.items()}
    val = {key: r["val_loss"] for key, r in records.items()}
    units = {key: r["val_loss_units"] for key, r in records.items()}
    print("\nother16, severe model, three draws")
    for plan in (*PLANS, *(p.replace("response@", "response+use@") for p in PLANS)):
        mean = np.mean([v[plan]["120"] for v in val.values()])
        print(f"{plan}: validation loss, mean over draws and folds {mean:.5f}")
    for key, m in choice_margins(val, data_family, units).items():
        interval = f"[{100 * m.lower:+.1f}, {100 * m.upper:+.1f}]%"
        print(f"{key}: best {m.method}, runner-up {m.runner_up}, margin {100 * m.margin:+.1f}%, "
              f"95% interval over {m.n} {m.over} {interval}: {m.verdict}")


if __name__ == "__main__":
    main()
    other16()
