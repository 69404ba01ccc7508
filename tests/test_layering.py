"""The package import table of ARCHITECTURE.md holds: each package imports only from the rows above
it (imports under TYPE_CHECKING and inside functions count too), and no two packages import
each other."""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1] / "research" / "anytip"
BASE = {"errors", "validation", "rundir"}
ALLOWED: dict[str, set[str]] = {name: BASE for name in BASE}
ALLOWED |= {
    "report": BASE,
    "sensor": BASE,
    "data": BASE | {"sensor"},
    "models": BASE | {"sensor", "data"},
    "train": BASE | {"data", "models"},
    "config": BASE | {"sensor", "data", "models", "train"},
    "uncertainty": BASE | {"data", "models", "train"},
    "deploy": BASE | {"data", "models", "train"},
    "search": BASE | {"data", "models", "train", "config", "deploy"},
    "analysis": BASE | {"sensor", "data", "models", "train"},
}
ALLOWED["calibrate"] = set(ALLOWED) | BASE
ALLOWED["pipelines"] = ALLOWED["calibrate"] | {"calibrate"}
ALLOWED["runner"] = ALLOWED["cli"] = ALLOWED["pipelines"] | {"pipelines", "runner", "cli"}


def package_of(path: Path) -> str:
    return path.relative_to(ROOT).with_suffix("").parts[0]


def imports_of(path: Path) -> set[str]:
    """Top-level anytip packages `path` imports, wherever the import statement is."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("anytip."):
            out.add(node.module.split(".")[1])
        elif isinstance(node, ast.ImportFrom) and node.module == "anytip":
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.Import):
            out |= {a.name.split(".")[1] for a in node.names if a.name.startswith("anytip.")}
    return out


def test_every_package_imports_only_what_the_table_allows():
    bad = []
    for path in sorted(ROOT.rglob("*.py")):
        pkg = package_of(path)
        if pkg == "__init__":
            continue
        assert pkg in ALLOWED, f"{path}: package {pkg!r} is not in the import table"
        for imported in imports_of(path) - {pkg}:
            if imported not in ALLOWED[pkg]:
                bad.append(f"{path.relative_to(ROOT)} imports anytip.{imported}")
    assert bad == []


def test_no_module_cycles():
    """No import cycle between modules (a package may not reach itself through another)."""
    graph: dict[str, set[str]] = defaultdict(set)
    modules = {".".join(p.relative_to(ROOT).with_suffix("").parts): p for p in ROOT.rglob("*.py")}
    for name, path in modules.items():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("anytip."):
                target = node.module[len("anytip."):]
                if target in modules:
                    graph[name].add(target)
    seen, stack, cycles = set(), [], []

    def visit(node: str) -> None:
        if node in stack:
            cycles.append(stack[stack.index(node):] + [node])
            return
        if node in seen:
            return
        seen.add(node)
        stack.append(node)
        for nxt in graph[node]:
            visit(nxt)
        stack.pop()

    for module in sorted(modules):
        visit(module)
    assert cycles == []
