"""Research log entry 145's gate on its registries: the runs other than the plan are the same in both, and
what each design's plan records per unit. Usage, from the repository root (logs/registries*.log):

    python reports/cross_sensor_response_gpu/entry145/check_registries.py 300 fleet88w3
    python reports/cross_sensor_response_gpu/entry145/check_registries.py 450 fleet88w45
"""

import sys
from collections import defaultdict

import numpy as np

from anytip.data.registry import Registry


def main(budget: str, name: str) -> None:
    plan = f"plan{budget}"
    runs = {n: Registry(f"data/{n}", create=False).list_runs() for n in (name, f"{name}f")}
    other = {n: sorted((r.run_id, r.sha256) for r in rs if r.protocol != plan) for n, rs in runs.items()}
    print(f"runs other than {plan}: {len(other[name])} and {len(other[f'{name}f'])}, "
          f"{'equal' if other[name] == other[f'{name}f'] else 'DIFFER'}")
    for n, rs in runs.items():
        mine = [r for r in rs if r.protocol == plan]
        per_unit: dict[str, float] = defaultdict(float)
        for r in mine:
            per_unit[r.unit] += r.duration_s
        d = np.array(list(per_unit.values()))
        print(f"{n}: {len(mine)} {plan} runs over {len(per_unit)} units, each unit's runs "
              f"{d.min():.1f}-{d.max():.1f} s of recording (re-mount not counted)")


if __name__ == "__main__":
    main(*sys.argv[1:3])
