"""Research log entry 109, after the rule: the correction's query blocks as `plan_correction` evaluates them
(`_kernel` and the product with the weights), float64 against float32, on 131,072 query rows and 1,024 plan
rows of five contact numbers and eight barometers, in blocks of 8,192, alternated five rounds; prints each
dtype's times and the largest difference relative to the largest value (`logs/kernel_time.log`). Usage, from
the repository root:

    OMP_NUM_THREADS=1 taskset -c 0 python reports/cross_sensor_response_gpu/entry109/kernel_time.py
"""

import time

import torch

from anytip.train.response import RESIDUAL_CHUNK, _kernel

torch.manual_seed(0)
POINTS = torch.randn(1024, 5, dtype=torch.float64)
QUERIES = torch.randn(131072, 5, dtype=torch.float64)
WEIGHTS = torch.randn(1024, 8, dtype=torch.float64)


def timed(dtype: torch.dtype) -> tuple[float, torch.Tensor]:
    """Seconds for every block in `dtype`, and the result."""
    t = time.perf_counter()
    near, weights = POINTS.to(dtype), WEIGHTS.to(dtype)
    out = torch.cat([_kernel(QUERIES[a:a + RESIDUAL_CHUNK].to(dtype), near, 1.0) @ weights
                     for a in range(0, len(QUERIES), RESIDUAL_CHUNK)])
    return time.perf_counter() - t, out


def main() -> None:
    times: dict[torch.dtype, list[float]] = {torch.float64: [], torch.float32: []}
    for r in range(5):
        (t64, y64), (t32, y32) = timed(torch.float64), timed(torch.float32)
        times[torch.float64].append(t64)
        times[torch.float32].append(t32)
        print(f"round {r}: largest difference {float((y32 - y64).abs().max() / y64.abs().max()):.1e} "
              "of the largest value")
    for dtype, ts in times.items():
        print(f"{dtype}: {' '.join(f'{t:.2f}' for t in ts)} s, median {sorted(ts)[2]:.2f} s")


if __name__ == "__main__":
    main()
