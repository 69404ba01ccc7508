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
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from anytip.errors import AnytipError
from anytip.rundir import builtin
from anytip.validation import format_validation_error, read_yaml

BUDGETS_DIR = builtin("configs") / "budgets"
# Fitted to the compiled float32 export of 8-12-64-64-5 and 8-16-5 (arm-none-eabi-gcc -O2):
# code and tables beyond the weights, RAM beyond the activation buffers, instructions.
CODE_BYTES, CODE_BYTES_PER_LAYER = 336, 20
RAM_OVERHEAD_BYTES = 68
INSTRUCTIONS_PER_MAC, INSTRUCTIONS_FIXED = 2.901, 416
# Beyond ReLU's code: instructions per hidden unit and code bytes of the other activations the
# float32 export computes without libm, fitted to the compiled 8-16-5, 8-32-32-5 and 8-12-64-64-5
# (leaky_relu 1.4-1.7 instructions and 20 B; hardswish 7.8-8.2 instructions and 40-60 B).
ACTIVATION_INSTRUCTIONS = {"relu": 0.0, "leaky_relu": 1.5, "hardswish": 8.0}
ACTIVATION_CODE_BYTES = {"relu": 0, "leaky_relu": 20, "hardswish": 60}


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
    if not path.is_file():
        known = sorted(p.stem for p in BUDGETS_DIR.glob("*.yaml"))
        raise AnytipError(f"{path}: cannot read budget (no such file); known budgets: {known}")
    data = read_yaml(path)
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
    activation: str = "relu"

    def to_json(self) -> dict:
        return asdict(self)


def params_and_macs(sizes: Sequence[int]) -> tuple[int, int]:
    """(weights + biases, multiply-accumulates) of an MLP with layer widths `sizes`."""
    pairs = list(zip(sizes[:-1], sizes[1:], strict=True))
    return sum((i + 1) * o for i, o in pairs), sum(i * o for i, o in pairs)


def check_activation(activation: str) -> None:
    """Only activations the float32 C export computes without libm have a cost."""
    if activation not in ACTIVATION_INSTRUCTIONS:
        raise AnytipError(f"activation {activation!r} does not export to the microcontroller (no libm); "
                          f"exportable: {list(ACTIVATION_INSTRUCTIONS)}")


def estimate(sizes: Sequence[int], budget: Budget, activation: str = "relu") -> Cost:
    """Cost from fitted overheads: flash = 4 params + code per layer, RAM = up to two activation
    buffers of the widest hidden layer + overhead, instructions = 2.90 per MAC + a fixed part
    + the activation's instructions per hidden unit beyond ReLU's."""
    check_activation(activation)
    params, macs = params_and_macs(sizes)
    n_layers, n_hidden = len(sizes) - 1, len(sizes) - 2
    width = max(sizes[1:-1], default=1)
    flash = 4 * params + CODE_BYTES + CODE_BYTES_PER_LAYER * n_layers + ACTIVATION_CODE_BYTES[activation]
    ram = 4 * width * min(n_hidden, 2) + RAM_OVERHEAD_BYTES
    extra = ACTIVATION_INSTRUCTIONS[activation] * sum(sizes[1:-1])
    instructions = int(round(INSTRUCTIONS_PER_MAC * macs + INSTRUCTIONS_FIXED + extra))
    return Cost(tuple(sizes), params, macs, flash, ram, instructions,
                int(round(instructions * budget.cycles_per_instruction)), False, False, activation)


def export_takes(activation: str) -> bool:
    """Whether the float32 C export (deploy/net.py's DeployNet) computes `activation`."""
    from dataclasses import fields

    from anytip.deploy.net import DeployNet

    return activation == "relu" or "activation" in {f.name for f in fields(DeployNet)}


def measure(sizes: Sequence[int], budget: Budget, instructions: bool = True,
            activation: str = "relu") -> Cost:
    """Cost of the emitted float32 C, compiled for Cortex-M4F (and run on the emulator): the
    activation's code is compiled and executed too."""
    from anytip.deploy.c_export import write_c
    from anytip.deploy.embedded import count_instructions, cross_compile, emulator_missing, toolchain_missing

    missing = toolchain_missing()
    if missing:
        raise AnytipError(f"cannot measure {list(sizes)}: {missing}")
    if not export_takes(activation):
        raise AnytipError(f"cannot measure {list(sizes)}: the C export does not take "
                          f"activation {activation!r}")
    net = _random_net(sizes, activation)
    guess = estimate(sizes, budget, activation)
    with tempfile.TemporaryDirectory() as tmp:
        _, source = write_c(net, tmp)
        size = cross_compile(source, Path(tmp) / "obj")
        n_instr, measured_instr = guess.instructions, False
        if instructions and emulator_missing() is None:
            n_instr, _ = count_instructions(source, net.in_mean.astype(np.float32), net.n_outputs)
            measured_instr = True
    return Cost(tuple(sizes), guess.params, guess.macs, size["flash_bytes"], size["ram_bytes"], n_instr,
                int(round(n_instr * budget.cycles_per_instruction)), True, measured_instr, activation)


def cost(sizes: Sequence[int], budget: Budget, measure_if_possible: bool = True,
         activation: str = "relu") -> Cost:
    """Measured where the toolchain is present and the export takes the activation, else
    estimated (and marked so)."""
    from anytip.deploy.embedded import toolchain_missing

    check_activation(activation)
    if measure_if_possible and toolchain_missing() is None and export_takes(activation):
        return measure(sizes, budget, activation=activation)
    return estimate(sizes, budget, activation)


def constraints(c: Cost, budget: Budget) -> tuple[float, float, float]:
    """Optuna-style constraints (feasible when every value <= 0): flash, RAM and time over
    their limits, as fractions of the limit."""
    t = c.cycles / budget.clock_hz
    return (c.flash_bytes / budget.flash_bytes_max - 1, c.ram_bytes / budget.ram_bytes_max - 1,
            t / budget.inference_s_max - 1)


def fits(c: Cost, budget: Budget) -> bool:
    return all(v <= 0 for v in constraints(c, budget))


def _random_net(sizes: Sequence[int], activation: str = "relu"):
    from anytip.deploy.net import DeployNet

    rng = np.random.default_rng(0)
    layers = [(rng.standard_normal((i, o)), rng.standard_normal(o))
              for i, o in zip(sizes[:-1], sizes[1:], strict=True)]
    d_in, d_out = sizes[0], sizes[-1]
    extra = {} if activation == "relu" else {"activation": activation}
    return DeployNet(layers, False, np.zeros(d_out), np.ones(d_out), np.zeros(d_in), np.ones(d_in),
                     [f"y{k}" for k in range(d_out)], "candidate", **extra)
