"""A shared MLP with small per-unit adapters that fold into a plain per-unit MLP.

The shared network has the deployed shape (sizes[0] -> ... -> sizes[-1]); unit m owns
only its adapter. An adapter kind is a '+'-joined set of parts:

- `input_affine`: x' = x @ A_m + c_m, A (d_in, d_in) starting at the identity;
- `input_diag`:   x' = x * a_m + c_m, the diagonal version (2 d_in numbers);
- `embedding`:    a per-unit first-layer bias e_m (a learned unit code of width h_1);
- `film`:         every hidden layer's pre-activation z -> z * gamma_m + beta_m (LHUC);
- `delta`:        a per-unit change of every weight and bias (fine-tuning, held as an
                  offset from the shared weights so a prior can pull it to zero);
- `lowrank<r>`:   a per-unit change of every weight of rank r, dW_l = U_l V_l with U_l
                  (in, r) starting at zero and V_l (r, out) at a fixed random draw shared by
                  every unit, plus a per-unit change of every bias (`lowrank2`: r = 2).

`none` is the bare shared network. Every part acts before a nonlinearity, so the adapted
network of unit m is exactly a plain MLP of the same shape: `fold` computes it.
Inputs and outputs are standardised outside this module (models/scaler.py); per-unit input
scalers are adapters too, set from unlabeled pressures.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence

import torch
from torch import Tensor, nn

from anytip.data.seeds import unit_seed
from anytip.errors import AnytipError
from anytip.models.mlp import ACTIVATIONS, BatchedMLP, MLPConfig

PARTS = ("input_affine", "input_diag", "embedding", "film", "delta", "lowrank<r>")
_LOWRANK = re.compile(r"lowrank([1-9][0-9]{0,2})")


def parse_kind(kind: str) -> frozenset[str]:
    """'input_affine+film' -> {'input_affine', 'film'}; 'none' -> {}; unknown parts raise."""
    parts = frozenset() if kind == "none" else frozenset(p.strip() for p in kind.split("+"))
    unknown = sorted(p for p in parts - set(PARTS) if not _LOWRANK.fullmatch(p))
    if unknown:
        raise AnytipError(f"adapter kind {kind!r}: unknown part(s) {unknown}; "
                          f"allowed: 'none' or a '+'-joined set of {list(PARTS)} (r from 1 to 999)")
    if {"input_affine", "input_diag"} <= parts:
        raise AnytipError(f"adapter kind {kind!r}: choose input_affine or input_diag, not both")
    if len([p for p in parts if p == "delta" or _LOWRANK.fullmatch(p)]) > 1:
        raise AnytipError(f"adapter kind {kind!r}: choose one of delta and lowrank<r>")
    return parts


def lowrank_rank(parts: frozenset[str]) -> int:
    """r of a kind's `lowrank<r>` part, 0 where it has none."""
    return next((int(m.group(1)) for p in parts if (m := _LOWRANK.fullmatch(p))), 0)


class AdaptedMLP(nn.Module):
    """Shared weights W_l (in, out), b_l (out,) plus adapters for `n_units` units.

    Adapter tensors are stacked over units, (U, 1, width) or (U, d_in, d_in), and start at
    the identity (scales 1, shifts 0), so an untrained adapter leaves the shared network
    unchanged. forward: x (U, B, d_in) standardised -> (U, B, d_out) standardised.
    """

    def __init__(self, n_units: int, config: MLPConfig, kind: str = "none", seed: int = 0):
        super().__init__()
        self.n_units, self.config, self.kind = n_units, config, kind
        self.parts = parse_kind(kind)
        sizes = config.sizes
        g = torch.Generator().manual_seed(unit_seed(seed, 0, "shared"))
        self.weights, self.biases = nn.ParameterList(), nn.ParameterList()
        for i, o in zip(sizes[:-1], sizes[1:], strict=True):
            bound = 1.0 / math.sqrt(i)
            self.weights.append(nn.Parameter(torch.empty(o, i).uniform_(-bound, bound, generator=g).T))
            self.biases.append(nn.Parameter(torch.empty(o).uniform_(-bound, bound, generator=g)))
        self.adapter = nn.ParameterDict(self.identity_adapter(n_units))

    def identity_adapter(self, n_units: int) -> dict[str, nn.Parameter]:
        """Adapter tensors of `n_units` units at the identity."""
        d_in, hidden = self.config.sizes[0], self.config.sizes[1:-1]
        t: dict[str, Tensor] = {}
        if "input_affine" in self.parts:
            t["in_A"] = torch.eye(d_in).repeat(n_units, 1, 1)
        if "input_diag" in self.parts:
            t["in_a"] = torch.ones(n_units, 1, d_in)
        if self.parts & {"input_affine", "input_diag"}:
            t["in_c"] = torch.zeros(n_units, 1, d_in)
        if "embedding" in self.parts:
            t["embed"] = torch.zeros(n_units, 1, hidden[0])
        if "film" in self.parts:
            for k, h in enumerate(hidden):
                t[f"gamma{k}"] = torch.ones(n_units, 1, h)
                t[f"beta{k}"] = torch.zeros(n_units, 1, h)
        if "delta" in self.parts:
            sizes = self.config.sizes
            for k, (i, o) in enumerate(zip(sizes[:-1], sizes[1:], strict=True)):
                t[f"dW{k}"] = torch.zeros(n_units, i, o)
                t[f"db{k}"] = torch.zeros(n_units, 1, o)
        if rank := lowrank_rank(self.parts):
            t |= self._lowrank_identity(n_units, rank)
        device = self.weights[0].device if len(self.weights) else None
        return {k: nn.Parameter(v.to(device)) for k, v in t.items()}

    def _lowrank_identity(self, n_units: int, rank: int) -> dict[str, Tensor]:
        """U_l zero and V_l one fixed draw (scaled 1/sqrt(r), so dW = U V starts with the
        gradient scale of a plain weight), the same for every unit and every model of this
        shape; bias changes zero."""
        g = torch.Generator().manual_seed(unit_seed(0, rank, "lowrank"))
        sizes, t = self.config.sizes, {}
        for k, (i, o) in enumerate(zip(sizes[:-1], sizes[1:], strict=True)):
            t[f"lU{k}"] = torch.zeros(n_units, i, rank)
            t[f"lV{k}"] = (torch.randn(rank, o, generator=g) / math.sqrt(rank)).repeat(n_units, 1, 1)
            t[f"db{k}"] = torch.zeros(n_units, 1, o)
        return t

    def reset_adapter(self, n_units: int) -> None:
        """Replace the adapters with `n_units` fresh identity adapters (for new units)."""
        self.n_units = n_units
        self.adapter = nn.ParameterDict(self.identity_adapter(n_units))

    def adapter_parameters(self) -> list[nn.Parameter]:
        return list(self.adapter.values())

    def shared_parameters(self) -> list[nn.Parameter]:
        return [*self.weights, *self.biases]

    def n_adapter_params(self) -> int:
        """Numbers one unit's adapter holds."""
        return sum(p[0].numel() for p in self.adapter.values())

    def _active(self, keep: Tensor | None) -> dict[str, Tensor]:
        """The adapter tensors in use: all of them, or with keep (U,) bool each unit whose keep
        is False at the identity (adapter dropout while training the shared weights)."""
        if keep is None:
            return dict(self.adapter)
        identity = self._identity_on(self.weights[0].device)
        k = keep.to(self.weights[0].dtype)
        return {n: identity[n] + k.view(-1, *([1] * (p.dim() - 1))) * (p - identity[n])
                for n, p in self.adapter.items()}

    def _input(self, x: Tensor, a: dict[str, Tensor]) -> Tensor:
        if "in_A" in a:
            x = torch.bmm(x, a["in_A"])
        if "in_a" in a:
            x = x * a["in_a"]
        if "in_c" in a:
            x = x + a["in_c"]
        return x

    def forward(self, x: Tensor, keep: Tensor | None = None) -> Tensor:
        """x (U, B, d_in) -> (U, B, d_out); `keep` (U,) bool drops the adapters of the units
        where it is False for this pass (see `_active`)."""
        return self.forward_with(x, self._active(keep))

    def forward_with(self, x: Tensor, a: dict[str, Tensor]) -> Tensor:
        """x (U, B, d_in) -> (U, B, d_out) with adapter tensors `a` (this model's keys, each
        (U, ...)) in place of its own: an adapter being fitted inside a training step."""
        act = ACTIVATIONS[self.config.activation]
        x = self._input(x, a)
        last = len(self.weights) - 1
        for k, (W, b) in enumerate(zip(self.weights, self.biases, strict=True)):
            if f"dW{k}" in a:
                x = torch.baddbmm(b + a[f"db{k}"], x, W + a[f"dW{k}"])
            elif f"lU{k}" in a:
                x = torch.baddbmm(x @ W + b + a[f"db{k}"], torch.bmm(x, a[f"lU{k}"]), a[f"lV{k}"])
            else:
                x = x @ W + b
            if k == 0 and "embed" in a:
                x = x + a["embed"]
            if k < last:
                if f"gamma{k}" in a:
                    x = x * a[f"gamma{k}"] + a[f"beta{k}"]
                x = act(x)
        if self.config.output_activation is not None:
            x = ACTIVATIONS[self.config.output_activation](x)
        return x

    def deviation(self) -> Tensor:
        """Squared distance of each unit's adapter from the identity, (U,): the few-shot prior."""
        device = self.weights[0].device
        out = torch.zeros(self.n_units, device=device)
        identity = self._identity_on(device)
        for k, p in self.adapter.items():
            out = out + ((p - identity[k]) ** 2).flatten(1).sum(1)
        return out

    def identity_like(self, n_units: int) -> dict[str, Tensor]:
        """`n_units` identity adapters as plain tensors on the model's device (no parameters)."""
        identity = self._identity_on(self.weights[0].device)
        return {k: v.expand(n_units, *v.shape[1:]).clone() for k, v in identity.items()}

    def _identity_on(self, device: torch.device) -> dict[str, Tensor]:
        """One unit's identity adapter on `device`, built once (deviation() runs every step)."""
        cache = self.__dict__.setdefault("_identity_cache", {})
        if device not in cache:
            cache[device] = {k: v.detach() for k, v in self.identity_adapter(1).items()}
        return cache[device]

    @torch.no_grad()
    def fold(self, units: Sequence[int] | None = None) -> BatchedMLP:
        """Plain per-unit MLPs of the same shape computing exactly this model's outputs.

        x @ A + c feeding layer 0 gives W_0' = A W_0, b_0' = c W_0 + b_0 (+ e); FiLM on layer
        k scales the columns: W_k' = W_k * gamma, b_k' = b_k * gamma + beta.
        """
        units = range(self.n_units) if units is None else units
        return BatchedMLP.from_plain([self._fold_one(m) for m in units], self.config)

    def _fold_one(self, m: int) -> list[tuple[Tensor, Tensor]]:
        a = self.adapter
        d_in = self.config.sizes[0]
        like = {"device": self.weights[0].device, "dtype": self.weights[0].dtype}
        A = a["in_A"][m] if "in_A" in a else torch.eye(d_in, **like)
        if "in_a" in a:
            A = torch.diag(a["in_a"][m, 0])
        c = a["in_c"][m, 0] if "in_c" in a else torch.zeros(d_in, **like)
        plain = []
        for k, (W, b) in enumerate(zip(self.weights, self.biases, strict=True)):
            W, b = W.detach().clone(), b.detach().clone()
            if f"dW{k}" in a:
                W, b = W + a[f"dW{k}"][m], b + a[f"db{k}"][m, 0]
            elif f"lU{k}" in a:
                W, b = W + a[f"lU{k}"][m] @ a[f"lV{k}"][m], b + a[f"db{k}"][m, 0]
            if k == 0:
                W, b = A @ W, c @ W + b
                if "embed" in a:
                    b = b + a["embed"][m, 0]
            if f"gamma{k}" in a:
                gamma, beta = a[f"gamma{k}"][m, 0], a[f"beta{k}"][m, 0]
                W, b = W * gamma, b * gamma + beta
            plain.append((W, b))
        return plain
