"""Embedded measures of an exported C model on a Cortex-M4F (STM32F334 class).

`cross_compile` builds the source with arm-none-eabi-gcc (-mcpu=cortex-m4 -mfpu=fpv4-sp-d16
-mfloat-abi=hard -Os/-O2) and reports section bytes: flash = text + rodata + data, RAM = data + bss
+ the stack of `anytip_infer` and its deepest callee (-fstack-usage). `count_instructions` links the
object alone at flash/RAM addresses and runs one `anytip_infer` call in the unicorn emulator
(Cortex-M4 CPU model, Thumb-2, FPU enabled through CPACR), counting executed instructions.
"""

from __future__ import annotations

import re
import shutil
import struct
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from anytip.errors import AnytipError

CC = "arm-none-eabi-gcc"
ARCH = ("-mcpu=cortex-m4", "-mthumb", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard", "-ffp-contract=fast")
OPT = "-O2"
FLASH, RAM = 0x08000000, 0x20000000
STACK_TOP = RAM + 0x10000
RETURN = 0x0800_FFF0  # any address outside the program: the emulator stops there
LINKER_SCRIPT = f"""
ENTRY(anytip_infer)
SECTIONS {{
  . = {FLASH:#x};
  .text : {{ *(.text*) *(.rodata*) }}
  . = {RAM:#x};
  .data : {{ *(.data*) }}
  .bss : {{ *(.bss*) *(COMMON) }}
}}
"""


def toolchain_missing() -> str | None:
    """Why cross-compiling cannot run here, or None when it can."""
    if shutil.which(CC) is None:
        return f"{CC} not found (Debian: apt-get install gcc-arm-none-eabi; scripts/system-deps.sh)"
    return None


def emulator_missing() -> str | None:
    """Why instruction counting cannot run here, or None when it can."""
    try:
        import unicorn  # noqa: F401
    except ImportError:
        return "the unicorn emulator is not installed (pip install unicorn; it is in the dev extras)"
    return toolchain_missing()


def _run(cmd: list[str]) -> str:
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        raise AnytipError(f"{' '.join(cmd[:2])} failed:\n{res.stderr.strip()}")
    return res.stdout


def _sections(path: Path) -> dict[str, int]:
    """Section name -> bytes (`size -A`)."""
    out = {}
    for line in _run(["arm-none-eabi-size", "-A", str(path)]).splitlines():
        parts = line.split()
        if len(parts) >= 3 and parts[0].startswith(".") and parts[1].isdigit():
            out[parts[0]] = out.get(parts[0], 0) + int(parts[1])
    return out


def _sum(sections: dict[str, int], prefix: str) -> int:
    return sum(v for k, v in sections.items() if k == prefix or k.startswith(prefix + "."))


def _stack_bytes(su: Path) -> int:
    """Stack of anytip_infer plus its largest callee frame, from gcc's -fstack-usage file."""
    frames = {m.group(1): int(m.group(2)) for m in re.finditer(r":(\w+)\s+(\d+)\s+\w+", su.read_text())}
    infer = frames.pop("anytip_infer", 0)
    return infer + max(frames.values(), default=0)


def _std(strict: bool) -> list[str]:
    return ["-std=c99", "-Wall", "-Wextra", "-Werror"] if strict else ["-std=gnu99"]


def cross_compile(source: str | Path, work: str | Path, includes: tuple[str, ...] = (),
                  strict: bool = True) -> dict[str, int]:
    """Object sizes for Cortex-M4F: text, rodata, data, bss, stack, flash and ram bytes (the object
    alone: a peer's calls into libm, if any, are not counted)."""
    source, work = Path(source), Path(work)
    work.mkdir(parents=True, exist_ok=True)
    obj = work / "anytip_model.o"
    _run([CC, *_std(strict), *ARCH, OPT, "-fstack-usage", "-I", str(source.parent),
          *[f"-I{d}" for d in includes], "-c", str(source), "-o", str(obj)])
    sec = _sections(obj)
    sizes = {"text": _sum(sec, ".text"), "rodata": _sum(sec, ".rodata"), "data": _sum(sec, ".data"),
             "bss": _sum(sec, ".bss"), "stack": _stack_bytes(obj.with_suffix(".su"))}
    sizes["flash_bytes"] = sizes["text"] + sizes["rodata"] + sizes["data"]
    sizes["ram_bytes"] = sizes["data"] + sizes["bss"] + sizes["stack"]
    return sizes


def link_for_emulator(source: str | Path, work: str | Path, includes: tuple[str, ...] = (),
                      strict: bool = True) -> Path:
    """An ELF with anytip_infer and its tables in flash and its buffers in RAM (no libraries)."""
    work = Path(work)
    work.mkdir(parents=True, exist_ok=True)
    ld, elf = work / "emu.ld", work / "anytip_emu.elf"
    ld.write_text(LINKER_SCRIPT)
    libs = [] if strict else ["-lm", "-lc", "-lgcc"]
    _run([CC, *_std(strict), *ARCH, OPT, "-nostartfiles", *([] if libs else ["-nostdlib"]),
          "-ffunction-sections", "-fdata-sections", "-Wl,--gc-sections",
          "-I", str(Path(source).parent), *[f"-I{d}" for d in includes], "-T", str(ld), str(source),
          "-o", str(elf), *libs])
    return elf


def _symbol(elf: Path, name: str) -> int:
    for line in _run(["arm-none-eabi-nm", str(elf)]).splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[2] == name:
            return int(parts[0], 16)
    raise AnytipError(f"{elf}: symbol {name!r} not found")


def _image(elf: Path, section_flags: list[str], work: Path) -> bytes:
    out = work / "img.bin"
    _run(["arm-none-eabi-objcopy", "-O", "binary", *section_flags, str(elf), str(out)])
    return out.read_bytes()


def count_instructions(source: str | Path, x: np.ndarray, n_out: int, includes: tuple[str, ...] = (),
                       strict: bool = True) -> tuple[int, np.ndarray]:
    """(instructions executed by one anytip_infer(x) on the emulated Cortex-M4, its outputs (n_out,))."""
    from unicorn import UC_ARCH_ARM, UC_HOOK_CODE, UC_MODE_MCLASS, UC_MODE_THUMB, Uc
    from unicorn import arm_const as A

    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        elf = link_for_emulator(source, work, includes, strict)
        text = _image(elf, ["-j", ".text"], work)
        data = _image(elf, ["-j", ".data"], work) if _sections(elf).get(".data") else b""
        entry = _symbol(elf, "anytip_infer")
    uc = Uc(UC_ARCH_ARM, UC_MODE_THUMB | UC_MODE_MCLASS)
    uc.ctl_set_cpu_model(A.UC_CPU_ARM_CORTEX_M4)
    uc.mem_map(FLASH, 0x100000)
    uc.mem_map(RAM, 0x20000)
    uc.mem_write(FLASH, text)
    uc.mem_write(RAM, data)
    x_addr, y_addr = RAM + 0x18000, RAM + 0x18000 + 4 * 1024
    uc.mem_write(x_addr, np.asarray(x, np.float32).tobytes())
    uc.reg_write(A.UC_ARM_REG_C1_C0_2, uc.reg_read(A.UC_ARM_REG_C1_C0_2) | (0xF << 20))  # CP10/CP11
    uc.reg_write(A.UC_ARM_REG_FPEXC, 0x40000000)
    uc.reg_write(A.UC_ARM_REG_SP, STACK_TOP)
    uc.reg_write(A.UC_ARM_REG_R0, x_addr)
    uc.reg_write(A.UC_ARM_REG_R1, y_addr)
    uc.reg_write(A.UC_ARM_REG_LR, RETURN | 1)
    count = [0]
    uc.hook_add(UC_HOOK_CODE, lambda *_: count.__setitem__(0, count[0] + 1))
    uc.emu_start(entry | 1, RETURN, count=50_000_000)
    y = np.array(struct.unpack(f"<{n_out}f", uc.mem_read(y_addr, 4 * n_out)), dtype=np.float64)
    return count[0], y
