"""Research log entries 98 and 100's tables: each validation unit's margin between two plans, paired, over
the folds (and start-network draws) that scored it. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry98/analyse.py fleet88
    python reports/cross_sensor_response_gpu/entry98/analyse.py other16
    python reports/cross_sensor_response_gpu/entry98/analyse.py fleet88w   # entry 100: SIM42-*
"""

import json
import sys
from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import _t_interval, _unit_logs

HERE = Path("reports/cross_sensor_response_gpu")
A, B = "response@cover", "response@cover_informative"
RUNS = {  # registry: (this entry's runs, entry 97's runs of the same folds, the added units' prefix)
    "fleet88": (sorted(HERE.glob("entry98/fleet88_seed*/val_loss_units.json")),
                sorted(HERE.glob("entry97/fleet88_cpu/fleet88_seed*/provenance.json")), "SIM41-"),
    "other16": (sorted(HERE.glob("entry98/other16_d*/other16_seed*/val_loss_units.json")),
                sorted(HERE.glob("entry97/other16_severe_d0/other16_seed*/provenance.json")), "SIM24-"),
    "fleet88w": (sorted(HERE.glob("entry100/fleet88_seed*/val_loss_units.json")),
                 sorted(HERE.glob("entry99/fleet88_cpu/fleet88_seed*/provenance.json")), "SIM42-"),
}


def records(files: list[Path]) -> dict[str, dict]:
    """{file: {method: {budget: {unit: loss}}}} of runs written by more_val.py or rescore_response.py."""
    out = {}
    for f in files:
        got = json.loads(f.read_text())
        if "val_loss_units" not in got:  # a rescored run's provenance
            (got,) = got["cross_sensor"].values()
        out[str(f)] = got["val_loss_units"]
    return out


def line(name: str, logs: np.ndarray) -> str:
    lo, hi = _t_interval(logs)
    verdict = "resolved" if lo > 0 or hi < 0 else "not resolved"
    mean = np.expm1(logs.mean()) * 100
    return (f"| {name} | {len(logs)} | {mean:+.1f}% | [{lo * 100:+.1f}, {hi * 100:+.1f}]% "
            f"| {int((logs < 0).sum())} / {int((logs > 0).sum())} | {verdict} |")


def main(registry: str) -> None:
    files, before, prefix = RUNS[registry]
    got = records(files)
    print(f"{registry}: {len(files)} runs")
    for f, rec in got.items():
        means = {m: np.mean(list(rec[m]["120"].values())) for m in (A, B)}
        print(f"- {f}: {len(rec[A]['120'])} units; mean {means[A]:.5f} / {means[B]:.5f}")
    logs = _unit_logs(got, A, B, 120.0)  # log(loss cover_informative / loss cover), a unit's runs averaged
    units = list(dict.fromkeys(u for rec in got.values() for u in rec[A]["120"] if u in rec[B]["120"]))
    new = np.array([u.startswith(prefix) for u in units])
    print("\n| validation units | n | margin of cover_informative over cover (mean) | 95% interval "
          "| favour cover_informative / cover | |\n|---|---|---|---|---|---|")
    print(line("all", logs))
    print(line(f"added ({prefix}*)", logs[new]))
    print(line("the registry's own", logs[~new]))
    old = records(before)
    print(f"\nthe registry's own units, this entry against {before[0].parts[2]} (cover; cover_informative):")
    for rec in got.values():
        for u in rec[A]["120"]:
            if u.startswith(prefix):
                continue
            was = [(r[A]["120"][u], r[B]["120"][u]) for r in old.values() if u in r[A]["120"]]
            print(f"- {u}: {rec[A]['120'][u]:.5f} {rec[B]['120'][u]:.5f} against "
                  + ", ".join(f"{a:.5f} {b:.5f}" for a, b in was))


if __name__ == "__main__":
    main(sys.argv[1])
