"""The benchmarks' one writer: a script's latest figures, dated, with the machine, into docs/benchmarks.md."""

from __future__ import annotations

import datetime
import os
import platform
import re
import sys
from pathlib import Path

PAGE = Path(__file__).resolve().parents[1] / "docs" / "benchmarks.md"
BEGIN = "<!-- figures: {script} -->"
END = "<!-- /figures: {script} -->"


def machine() -> str:
    """The machine the figures ran on: CPU model, cores, memory, system, Python."""
    model = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text(encoding="utf-8").splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    memory = ""
    try:
        pages, size = os.sysconf("SC_PHYS_PAGES"), os.sysconf("SC_PAGE_SIZE")
        memory = f", {pages * size / 2**30:.0f} GB"
    except (ValueError, OSError, AttributeError):
        pass
    return (
        f"{model}, {os.cpu_count()} cores{memory}, {platform.system()} {platform.release()}, "
        f"Python {platform.python_version()}"
    )


def block(script: str, command: str, lines: list[str], day: datetime.date, where: str) -> str:
    """The page's block of one script: its markers, the date, the machine, the command and the figures."""
    body = "\n".join(lines).rstrip("\n")
    return (
        f"{BEGIN.format(script=script)}\n"
        f"Latest figures: {day.isoformat()}, on {where}; `{command}`.\n\n"
        f"```text\n{body}\n```\n"
        f"{END.format(script=script)}"
    )


def replace_block(page: str, script: str, new_block: str) -> str:
    """The page with the script's block replaced (or added at the end, under a heading of its name)."""
    pattern = re.compile(re.escape(BEGIN.format(script=script)) + r".*?" + re.escape(END.format(script=script)), re.S)
    if pattern.search(page):
        return pattern.sub(lambda _match: new_block, page, count=1)
    return page.rstrip("\n") + f"\n\n## `{script}`\n\n{new_block}\n"


class Figures:
    """What a benchmark prints, kept: `line` prints and keeps a line, `write` puts them into the page."""

    def __init__(self, script: str) -> None:
        self.script = Path(script).name
        self.lines: list[str] = []

    def line(self, text: str = "") -> None:
        print(text, flush=True)
        self.lines.append(text)

    def write(self, page: Path = PAGE, day: datetime.date | None = None, where: str | None = None) -> None:
        day = day or datetime.datetime.now(datetime.UTC).date()
        command = " ".join(["python", f"benchmarks/{self.script}", *sys.argv[1:]])
        text = page.read_text(encoding="utf-8")
        new = replace_block(text, self.script, block(self.script, command, self.lines, day, where or machine()))
        staged = page.with_name(f".{page.name}.{os.getpid()}.new")
        staged.write_text(new, encoding="utf-8")
        os.replace(staged, page)  # the page whole, old or new
        print(f"figures written to {page}", file=sys.stderr)
