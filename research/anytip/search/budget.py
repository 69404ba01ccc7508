"""What a candidate MLP costs on the sensor's microcontroller, and whether it fits.

`cost(sizes)` gives parameters, MACs, flash and RAM bytes of the float32 C that `anytip
export` emits, and cycles per inference. Where the Cortex-M4F cross toolchain is installed,
flash and RAM are measured from the compiled object (random weights of the right shape:
sizes do not depend on values) and cycles from instructions executed on the emulator when
it is installed; otherwise (and for what could not be measured) they are estimated from
the measured cost of the paper's MLP and marked `measured: False`.
"""

from __future__ import annotations

import tempfile
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from anytip.errors import AnytipError
from anytip.validation import format_validation_error

BUDGETS_DIR = Path(__file__).resolve().parents[3] / "configs" / "budgets"
# Fitted to the compiled float32 export of 8-12-64-64-5 and 8-16-5 (arm-none-eabi-gcc -O2):
# code and tables beyond the weights, RAM beyond the activation buffers, instructions.
CODE_BYTES, CODE_BYTES_PER_LAYER = 324, 40
RAM_OVERHEAD_BYTES = 92
INSTRUCTIONS_PER_MAC, INSTRUCTIONS_FIXED = 2.917, 403


class Budget(BaseModel):
    """A microcontroller budget for one model (configs/budgets/*.yaml)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str
    mcu: str = ""
    clock_hz: float = Field(gt=0)
    flash_total_bytes: int = Field(gt=0)
    flash_bytes_max: int = Field(gt=0)
    ram_bytes_max: int = Field(gt=0)
    sample_rate_hz: float = Field(gt=0)
    inference_fraction_max: float = Field(gt=0, le=1)
    cycles_per_instruction: float = Field(1.0, gt=0)

    @property
    def inference_s_max(self) -> float:
        return self.inference_fraction_max / self.sample_rate_hz


def load_budget(name_or_path: str | Path) -> Budget:
    """A budget by name (configs/budgets/NAME.yaml) or path; errors name the file and key."""
    path = Path(name_or_path)
    if not path.suffix:
        path = BUDGETS_DIR / f"{name_or_path}.yaml"
    try:
        data = yaml.safe_load(path.read_text())
    except OSError as e:
        known = sorted(p.stem for p in BUDGETS_DIR.glob("*.yaml"))
        raise AnytipError(f"{path}: cannot read budget ({e.strerror}); known budgets: {known}") from None
    try:
        return Budget.model_validate(data or {})
    except ValidationError as e:
        raise AnytipError(format_validation_error(e, str(path), Budget)) from None


@dataclass(frozen=True)
class Cost:
    """One candidate's cost: bytes, MACs, cycles (and seconds at the budget's clock)."""

    sizes: tuple[int, ...]
    params: int
    macs: int
    flash_bytes: int
    ram_bytes: int
    instructions: int
    cycles: int
    measured_sizes: bool
    measured_instructions: bool

    def to_json(self) -> dict:
        return asdict(self)


def params_and_macs(sizes: Sequence[int]) -> tuple[int, int]:
    """(weights + biases, multiply-accumulates) of an MLP with layer widths `sizes`."""
    pairs = list(zip(sizes[:-1], sizes[1:], strict=True))
    return sum((i + 1) * o for i, o in pairs), sum(i * o for i, o in pairs)


def estimate(sizes: Sequence[int], budget: Budget) -> Cost:
    """Cost from fitted overheads: flash = 4 params + code per layer, RAM = up to two activation
    buffers of the widest hidden layer + overhead, instructions = 2.92 per MAC + a fixed part."""
    params, macs = params_and_macs(sizes)
    n_layers, n_hidden = len(sizes) - 1, len(sizes) - 2
    width = max(sizes[1:-1], default=1)
    flash = 4 * params + CODE_BYTES + CODE_BYTES_PER_LAYER * n_layers
    ram = 4 * width * min(n_hidden, 2) + RAM_OVERHEAD_BYTES
    instructions = int(round(INSTRUCTIONS_PER_MAC * macs + INSTRUCTIONS_FIXED))
    return Cost(tuple(sizes), params, macs, flash, ram, instructions,
                int(round(instructions * budget.cycles_per_instruction)), False, False)


def measure(sizes: Sequence[int], budget: Budget, instructions: bool = True) -> Cost:
    """Cost of the emitted float32 C, compiled for Cortex-M4F (and run on the emulator)."""
    from anytip.deploy.c_export import write_c
    from anytip.deploy.embedded import count_instructions, cross_compile, emulator_missing, toolchain_missing

    missing = toolchain_missing()
    if missing:
        raise AnytipError(f"cannot measure {list(sizes)}: {missing}")
    net = _random_net(sizes)
    guess = estimate(sizes, budget)
    with tempfile.TemporaryDirectory() as tmp:
        _, source = write_c(net, tmp)
        size = cross_compile(source, Path(tmp) / "obj")
        n_instr, measured_instr = guess.instructions, False
        if instructions and emulator_missing() is None:
            n_instr, _ = count_instructions(source, net.in_mean.astype(np.float32), net.n_outputs)
            measured_instr = True
    return Cost(tuple(sizes), guess.params, guess.macs, size["flash_bytes"], size["ram_bytes"], n_instr,
                int(round(n_instr * budget.cycles_per_instruction)), True, measured_instr)


def cost(sizes: Sequence[int], budget: Budget, measure_if_possible: bool = True) -> Cost:
    """Measured where the toolchain is present, else estimated (and marked so)."""
    from anytip.deploy.embedded import toolchain_missing

    if measure_if_possible and toolchain_missing() is None:
        return measure(sizes, budget)
    return estimate(sizes, budget)


def constraints(c: Cost, budget: Budget) -> tuple[float, float, float]:
    """Optuna-style constraints (feasible when every value <= 0): flash, RAM and time over
    their limits, as fractions of the limit."""
    t = c.cycles / budget.clock_hz
    return (c.flash_bytes / budget.flash_bytes_max - 1, c.ram_bytes / budget.ram_bytes_max - 1,
            t / budget.inference_s_max - 1)


def fits(c: Cost, budget: Budget) -> bool:
    return all(v <= 0 for v in constraints(c, budget))


def _random_net(sizes: Sequence[int]):
    from anytip.deploy.net import DeployNet

    rng = np.random.default_rng(0)
    layers = [(rng.standard_normal((i, o)), rng.standard_normal(o))
              for i, o in zip(sizes[:-1], sizes[1:], strict=True)]
    d_in, d_out = sizes[0], sizes[-1]
    return DeployNet(layers, False, np.zeros(d_out), np.ones(d_out), np.zeros(d_in), np.ones(d_in),
                     [f"y{k}" for k in range(d_out)], "candidate")
