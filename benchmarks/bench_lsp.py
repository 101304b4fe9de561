"""Diagnostics of the language server after an edit of a 2,000-line KRL program (goal: within 0.5 s, issue 41).

The program: the KRL program codegen generates for a cell of --stations stations (bench_render.py's cell; 55 make a
.src of about 2,000 lines, with its .dat). The server (`codegen lsp`, its default debounce) runs as an editor starts
it; a client opens the .src, waits for its first check, then edits one line --repeat times, alternately writing an
undefined name into it and taking it out again. Per edit: the time from sending the change to the first diagnostics
published for the file (this file's syntax, with what the last whole check said of the rest) and to the whole
program's check that shows the edit (the undefined name found, or gone), and the CPU time the server's process spent
from sending the edit to that check (user + system, all its threads, read from /proc). Median and range over the edits;
the server's resident memory after them.

Run: python benchmarks/bench_lsp.py [--stations N] [--repeat N]
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from bench_render import make_cell
from lsprotocol import types
from pygls.lsp.client import LanguageClient
from record import Figures

FIGURES = Figures(__file__)
GOAL_S = 0.5
GOOD, BAD = "  VIS_STOPPED = FALSE", "  VIS_STOPED = FALSE"  # a line of every station program's main routine


def program(folder: Path, stations: int) -> Path:
    from codegen.generate import generate
    from codegen.model.cell import load_cell

    cell = folder / "bench_cell.toml"
    cell.write_text(make_cell(stations), encoding="utf-8")
    generate(load_cell(cell), ["kuka"], folder / "out")
    return next((folder / "out").rglob("*.src"))


def cpu_s(pid: int) -> float:
    """The CPU time (user + system, every thread) a process has used, from /proc/<pid>/stat (Linux)."""
    fields = Path(f"/proc/{pid}/stat").read_text(encoding="ascii").rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def rss_mb(pid: int) -> float:
    """A process's resident memory (MB), from /proc/<pid>/status (Linux)."""
    for line in Path(f"/proc/{pid}/status").read_text(encoding="ascii").splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


async def measure(src: Path, repeat: int) -> tuple[list[float], list[float], list[float], float]:
    client = LanguageClient("bench-lsp", "1")
    published: asyncio.Queue = asyncio.Queue()

    @client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def on_diagnostics(params: types.PublishDiagnosticsParams) -> None:
        if params.uri == src.as_uri():
            published.put_nowait((time.perf_counter(), params.diagnostics))

    await client.start_io(sys.executable, "-m", "codegen", "lsp")
    pid = client._server.pid  # pygls's LanguageClient keeps the server's process there
    await client.initialize_async(
        types.InitializeParams(capabilities=types.ClientCapabilities(), root_uri=src.parent.as_uri())
    )
    client.initialized(types.InitializedParams())
    text = src.read_text(encoding="utf-8")
    assert GOOD in text
    uri = src.as_uri()
    item = types.TextDocumentItem(uri=uri, language_id="krl", version=1, text=text)
    client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=item))
    await _whole_check(published, lambda found: not any(d.code != "syntax" for d in found) or True)
    await _drain(published)
    first, whole, cpu = [], [], []
    for version in range(2, repeat + 2):
        broken = version % 2 == 0
        new = text.replace(GOOD, BAD, 1) if broken else text
        change = types.TextDocumentContentChangeWholeDocument(text=new)
        document = types.VersionedTextDocumentIdentifier(uri=uri, version=version)
        start, used = time.perf_counter(), cpu_s(pid)
        client.text_document_did_change(types.DidChangeTextDocumentParams(document, [change]))
        when, _found = await published.get()
        first.append(when - start)
        if broken:
            done = await _whole_check(published, lambda found: any(d.code == "undefined-name" for d in found))
        else:
            done = await _whole_check(published, lambda found: not found)
        whole.append(done - start)
        cpu.append(cpu_s(pid) - used)
        await _drain(published)
    memory = rss_mb(pid)
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    return first, whole, cpu, memory


async def _whole_check(published: asyncio.Queue, settled) -> float:
    while True:
        when, found = await asyncio.wait_for(published.get(), 120)
        if settled(found):
            return when


async def _drain(published: asyncio.Queue) -> None:
    await asyncio.sleep(0.3)
    while not published.empty():
        published.get_nowait()


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--stations", type=int, default=55)
    parser.add_argument("--repeat", type=int, default=20)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        src = program(Path(tmp), args.stations)
        lines = len(src.read_text(encoding="utf-8").split("\n"))
        dat = len(src.with_suffix(".dat").read_text(encoding="utf-8").split("\n"))
        first, whole, cpu, memory = asyncio.run(measure(src, args.repeat))
    FIGURES.line(f"KRL program of {args.stations} stations: .src {lines} lines, .dat {dat} lines; {args.repeat} edits")
    for name, times in (("first diagnostics (the file's syntax)", first), ("the whole program's check", whole)):
        median = statistics.median(times)
        verdict = "ok" if median <= GOAL_S else "OVER GOAL"
        FIGURES.line(
            f"{name}: median {median:.3f} s, range {min(times):.3f}-{max(times):.3f} s (goal <= {GOAL_S} s): {verdict}"
        )
    FIGURES.line(
        f"server CPU per edit (to the whole check): median {statistics.median(cpu):.3f} s, "
        f"range {min(cpu):.3f}-{max(cpu):.3f} s"
    )
    FIGURES.line(f"server memory (resident) after the edits: {memory:.0f} MB")
    FIGURES.line(f"load average (1 min) at the end: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    FIGURES.line("times from sending the edit, the server's debounce (0.1 s) included")
    return 0 if statistics.median(whole) <= GOAL_S else 1


if __name__ == "__main__":
    code = main()
    FIGURES.write()  # the figures into docs/benchmarks.md, dated, with the machine
    sys.exit(code)
