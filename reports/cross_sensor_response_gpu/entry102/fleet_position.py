"""Research log entry 102, rule 1's search for a cause: does a member's prediction depend on its place in a
batched fleet? Random networks of the deployed shape (88 members, as the rescoring's fleet), predicted with
the fleet's halves swapped; prints the elements that differ per output (`logs/fleet_position.log`). Usage,
from the repository root:

    OMP_NUM_THREADS=1 python reports/cross_sensor_response_gpu/entry102/fleet_position.py
"""

import torch

from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.models.scaler import Scaler
from anytip.train.metrics import predict

U, N = 88, 20000


def main() -> None:
    torch.manual_seed(0)
    config = MLPConfig()
    nets, swapped = BatchedMLP(U, config), BatchedMLP(U, config)
    perm = torch.cat([torch.arange(U // 2, U), torch.arange(0, U // 2)])
    with torch.no_grad():
        for p, q in zip(nets.parameters(), swapped.parameters(), strict=True):
            p.normal_(0, 0.5)
            q.copy_(p[perm])
    ins = Scaler(torch.randn(U, 1, 8) * 1000, torch.rand(U, 1, 8) * 500 + 100)
    outs = Scaler(torch.randn(U, 1, 5), torch.rand(U, 1, 5) + 0.5)
    X = torch.randn(U, N, 8) * 500 + 1000
    a = predict(nets, ins, outs, X)
    moved = [Scaler(s.mean[perm], s.std[perm]) for s in (ins, outs)]
    b = predict(swapped, *moved, X[perm])
    print(f"{config.sizes}, {U} members x {N} rows: elements that differ per output",
          (a[perm] != b).sum((0, 1)).tolist())


if __name__ == "__main__":
    main()
