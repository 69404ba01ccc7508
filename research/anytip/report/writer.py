"""The one report writer: a pipeline adds its markdown blocks and figures to a `Report`, in reading
order, and `write()` saves `report.md` in the run directory.

Every pipeline's report goes through it, so every report is written the same way: atomically,
ending in a newline, figures saved beside it as PNG, and a hand-written `reading.md` kept in
the run directory (what a committed report's figures mean) appended after the generated text,
so a rerun keeps the reading and marks it for re-checking.
"""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure

from anytip.report.figures import save_figure
from anytip.report.markdown import image
from anytip.rundir import write_text

REPORT, READING = "report.md", "reading.md"


class Report:
    """Markdown blocks and figures of one run's report (see the module docstring)."""

    def __init__(self, run_dir: str | Path):
        self.run_dir = Path(run_dir)
        self.blocks: list[str] = []

    def add(self, *blocks: str) -> Report:
        """Append markdown blocks (they are joined by the separator `write` is given)."""
        self.blocks.extend(blocks)
        return self

    def figure(self, fig: Figure, name: str, alt: str) -> str:
        """Save `fig` as `name` (PNG) in the run directory; returns its markdown image link."""
        save_figure(fig, self.run_dir / name)
        return image(name, alt)

    def reading(self) -> str:
        """The run directory's hand-written `reading.md`, marked, or '' when there is none."""
        path = self.run_dir / READING
        if not path.exists():
            return ""
        return (f"\n<!-- from {READING}: written by hand for this run; check it against the tables above "
                f"after a rerun -->\n{path.read_text()}")

    def write(self, sep: str = "\n") -> Path:
        """Write the blocks joined by `sep`, then the reading, as `report.md`; returns its path."""
        text = sep.join(self.blocks)
        text = (text if text.endswith("\n") else text + "\n") + self.reading()
        path = self.run_dir / REPORT
        write_text(path, text)
        return path
