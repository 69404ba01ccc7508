"""Research log entry 101, rule 5 after it: the correction's kernel as it was (`cdist`, its root squared
again) against squared distances from one product (`plan_correction` now), on 131,072 query rows and 1,024
plan rows of five contact numbers in float64, in blocks of 8,192, alternated five rounds; prints each
round's largest difference (relative to the largest value) and the times (`logs/kernel_time.log`). Usage,
from the repository root:

    OMP_NUM_THREADS=1 taskset -c 0 python reports/cross_sensor_response_gpu/entry101/kernel_time.py
"""

import time
from collections.abc import Callable

import torch

from anytip.train.response import RESIDUAL_CHUNK

torch.manual_seed(0)
POINTS = torch.randn(1024, 5, dtype=torch.float64)
QUERIES = torch.randn(131072, 5, dtype=torch.float64)
WEIGHTS = torch.randn(1024, 8, dtype=torch.float64)
NORMS = POINTS.pow(2).sum(1)


def before(a: torch.Tensor) -> torch.Tensor:
    return torch.cdist(a, POINTS).pow_(2).div_(-2.0).exp_()


def now(a: torch.Tensor) -> torch.Tensor:
    d2 = torch.addmm(NORMS, a, POINTS.T, alpha=-2).add_(a.pow(2).sum(1, keepdim=True)).clamp_min_(0)
    return d2.div_(-2.0).exp_()


def timed(kernel: Callable[[torch.Tensor], torch.Tensor]) -> tuple[float, torch.Tensor]:
    t = time.perf_counter()
    out = torch.cat([kernel(QUERIES[a:a + RESIDUAL_CHUNK]) @ WEIGHTS
                     for a in range(0, len(QUERIES), RESIDUAL_CHUNK)])
    return time.perf_counter() - t, out


def main() -> None:
    times: dict[str, list[float]] = {"before": [], "now": []}
    for r in range(5):
        (t0, y0), (t1, y1) = timed(before), timed(now)
        times["before"].append(t0)
        times["now"].append(t1)
        gap = float((y1 - y0).abs().max() / y0.abs().max())
        print(f"round {r}: largest difference {gap:.1e} of the largest value")
    for name, ts in times.items():
        print(f"{name}: {' '.join(f'{t:.2f}' for t in ts)} s, median {sorted(ts)[2]:.2f} s")


if __name__ == "__main__":
    main()
