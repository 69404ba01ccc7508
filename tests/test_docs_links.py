"""Every relative link in the project's Markdown (README, docs, reports) leads to a file that exists, and
every `#anchor` to a heading of its target, so that a reader following a figure to its report or research
log entry never lands on nothing."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SKIP = {".git", ".venv", "build", "data", "runs", "node_modules"}
LINK = re.compile(r"\]\(([^)\s]+)\)")
HEADING = re.compile(r"^#+ (.*)$", re.MULTILINE)


def markdown_files() -> list[Path]:
    """The project's Markdown files, outside environments, data and build outputs."""
    return sorted(p for p in ROOT.rglob("*.md") if not SKIP & set(p.relative_to(ROOT).parts[:-1]))


def anchors(path: Path) -> set[str]:
    """The anchors GitHub gives `path`'s headings: lower case, punctuation but '-' and '_' dropped, spaces
    as '-'."""
    return {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-")
            for h in HEADING.findall(path.read_text(encoding="utf-8"))}


def broken_links(path: Path) -> list[str]:
    """`path`'s relative links whose file is missing, or whose anchor names no heading there."""
    broken = []
    for link in LINK.findall(path.read_text(encoding="utf-8")):
        if re.match(r"[a-z][a-z0-9+.-]*:", link):
            continue  # http:, https:, mailto:
        target, _, anchor = link.partition("#")
        file = (path.parent / target) if target else path
        if not file.exists():
            broken.append(f"{link} (no such file)")
        elif anchor and file.suffix == ".md" and anchor not in anchors(file):
            broken.append(f"{link} (no such heading)")
    return broken


def test_the_anchor_rule_follows_githubs():
    assert anchors(ROOT / "docs" / "cross_sensor.md") >= {"the-model", "where-the-targets-stand-in-detail"}


def test_every_relative_link_in_the_projects_markdown_resolves():
    files = markdown_files()
    assert any(p.name == "research_log.md" for p in files) and len(files) > 100
    broken = {str(p.relative_to(ROOT)): b for p in files if (b := broken_links(p))}
    assert not broken, broken


def test_a_missing_file_and_a_missing_heading_are_both_found(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("# Title here\n[a](page.md#title-here) [b](gone.md) [c](#nowhere) [d](https://x.org/y)\n")
    assert broken_links(page) == ["gone.md (no such file)", "#nowhere (no such heading)"]
