"""Progress on a terminal (rich): the plant's cells done and the current cell's runs; nothing where the output is
not a terminal (CI logs stay clean)."""

from __future__ import annotations

import sys
from contextlib import contextmanager

from codegen.terminal import inert, own_controls


class Quiet:
    """Progress that shows nothing."""

    def cell(self, label: str) -> None:
        pass

    def runs(self, count: int) -> None:
        pass

    def done(self) -> None:
        pass


class Bars(Quiet):
    """Two rich tasks: cells done of the plant's, and the runs of the cell at work."""

    def __init__(self, progress, total: int):
        self.progress = progress
        self.cells = progress.add_task("cells", total=total)
        self.current = progress.add_task("", total=None)

    def cell(self, label: str) -> None:
        self.progress.reset(self.current, total=None, description=inert(label))

    def runs(self, count: int) -> None:
        self.progress.advance(self.current, count)

    def done(self) -> None:
        self.progress.advance(self.cells)


def wanted(stream=None) -> bool:
    """Bars where the stream (stderr) is a terminal."""
    stream = stream or sys.stderr
    return hasattr(stream, "isatty") and stream.isatty()


@contextmanager
def progress_bars(total: int, enabled: bool):
    """Bars on stderr when enabled, else Quiet; the bars vanish when the work ends (the table follows)."""
    if not enabled:
        yield Quiet()
        return
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    columns = (
        SpinnerColumn(),
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
    )
    console = Console(file=own_controls(sys.stderr), stderr=True)  # the bars' own redraws, beneath the door
    with Progress(*columns, console=console, transient=True) as progress:
        yield Bars(progress, total)
