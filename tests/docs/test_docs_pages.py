"""The documentation speaks of the product as it is: no sessions, issues or earlier states; the files it names
exist; the benchmarks write their figures into docs/benchmarks.md, dated, with the machine."""

from __future__ import annotations

import datetime
import re
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "benchmarks"))
import record  # noqa: E402  (benchmarks/ is not a package: its scripts import it the same way)

PAGES = [REPO / "README.md", REPO / "CHANGELOG.md", *sorted((REPO / "docs").rglob("*.md"))]
INCLUDE = re.compile(r'^--8<-- "(?P<path>[^":]+)(?::[-\d:]*)?"\s*$', re.M)  # a file the site shows in a page
# words of history or of how the work was organised: a page says what the product does, not how it got there
HISTORY = re.compile(
    r"\b(sessions?|issues?|helpers?|no longer|now|nowadays|today|previously|formerly|used to|as before|"
    r"until this release|at filing|yet|since version|was:)\b|\(was\b",
    re.IGNORECASE,
)
CODE = re.compile(r"^(\s*)(`{3,}|~{3,}).*?^\1\2\s*$|`[^`\n]+`", re.M | re.S)  # fenced blocks, inline code
PATH = re.compile(r"\b(?:codegen|tests|benchmarks|targets|templates|docs|generated)/[\w./*-]*[\w*/]")
SCRIPTS = sorted([*(REPO / "benchmarks").glob("bench_*.py"), REPO / "benchmarks" / "refine_convergence.py"])


def prose(text: str) -> str:
    """The text without its code (blocks and inline spans), lines kept where they were."""
    return CODE.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def shown_files() -> list[Path]:
    """The pages and the files they include."""
    out = list(PAGES)
    for page in PAGES:
        out += [REPO / m["path"] for m in INCLUDE.finditer(page.read_text(encoding="utf-8"))]
    return out


@pytest.mark.parametrize("path", shown_files(), ids=lambda p: str(p.relative_to(REPO)))
def test_no_page_speaks_of_history(path):
    text = prose(path.read_text(encoding="utf-8"))
    found = [
        f"{path.relative_to(REPO)}:{text.count(chr(10), 0, m.start()) + 1}: {m.group(0)!r}"
        for m in HISTORY.finditer(text)
    ]
    assert not found, found


def test_the_history_check_finds_what_it_looks_for():
    for said in ("as in the last session", "before issue 11", "it is now faster", "no longer needed", "(was 7 s)"):
        assert HISTORY.search(prose(said)), said
    assert not HISTORY.search(prose("the station's `helpers()` macro; the mark at calibration")), "code"


OTHERS = re.compile(r"[\w.-]+/[\w.-]+: `[^`\n]*`")  # another repository's files, named after it ("owner/name: `path`")


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(REPO)))
def test_the_files_a_page_names_exist(page):
    missing = []
    for match in PATH.finditer(OTHERS.sub("", page.read_text(encoding="utf-8"))):
        name = match.group(0).rstrip(".")
        if "..." in name or name.endswith(("/.", "_")):
            continue
        found = list(REPO.glob(name.rstrip("/"))) if "*" in name else [REPO / name]
        if not found or not all(p.exists() for p in found):
            missing.append(name)
    assert not missing, f"{page.relative_to(REPO)} names files that do not exist: {missing}"


def test_the_writer_replaces_a_scripts_block_and_keeps_the_rest(tmp_path):
    page = tmp_path / "benchmarks.md"
    old = record.block("bench_x.py", "python benchmarks/bench_x.py", ["old 1"], datetime.date(2020, 1, 2), "m1")
    page.write_text(f"# Benchmarks\n\nintro\n\n{old}\n\nafter\n", encoding="utf-8")
    figures = record.Figures("benchmarks/bench_x.py")
    figures.line("rate 12 cases/s")
    figures.write(page, datetime.date(2031, 5, 6), "the test machine, 2 cores")
    text = page.read_text(encoding="utf-8")
    assert "old 1" not in text and "2020-01-02" not in text
    assert "Latest figures: 2031-05-06, on the test machine, 2 cores;" in text
    assert "```text\nrate 12 cases/s\n```" in text
    assert text.startswith("# Benchmarks\n\nintro\n\n<!-- figures: bench_x.py -->") and text.endswith("\n\nafter\n")
    figures = record.Figures("bench_new.py")
    figures.line("1 s")
    figures.write(page, datetime.date(2031, 5, 7), "m")
    text = page.read_text(encoding="utf-8")
    assert text.count("<!-- figures: bench_x.py -->") == 1 and "## `bench_new.py`" in text
    assert text.rstrip().endswith("<!-- /figures: bench_new.py -->")
    assert "cores" in record.machine() and "Python" in record.machine()


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_every_benchmark_writes_its_block_of_the_page(script):
    text = script.read_text(encoding="utf-8")
    assert "FIGURES = Figures(__file__)" in text and "FIGURES.write()" in text
    assert not re.search(r"^\s+print\(", text, re.M), "a figure printed but not kept: use FIGURES.line"
    page = record.PAGE.read_text(encoding="utf-8")
    begin, end = (re.escape(marker.format(script=script.name)) for marker in (record.BEGIN, record.END))
    block = re.search(begin + r"\n(.*?)" + end, page, re.S)
    assert block, f"docs/benchmarks.md has no block for {script.name}"
    assert re.match(r"Latest figures: \d{4}-\d\d-\d\d, on .+", block.group(1)), block.group(1)[:80]


def test_the_arm_table_names_every_arm_of_the_catalogue():
    """The arm page's table left out the UR20."""
    from codegen.robot.arms import catalogue

    text = (REPO / "docs" / "arm.md").read_text(encoding="utf-8")
    families = ("| ur |", "| opw |")
    lines = [line for line in text.splitlines() if line.startswith("| ")]
    rows = [line.split("|")[1] for line in lines if any(f in line for f in families)]
    listed = {name.strip() for row in rows for name in row.split(",")}
    assert set(catalogue()) <= listed, sorted(set(catalogue()) - listed)


def test_the_navigation_names_pages_by_what_they_do_not_by_source_number():
    """The kinds' pages were listed as "Point stations (source 000)" ...: a number a new user cannot read."""
    nav = (REPO / "mkdocs.yml").read_text(encoding="utf-8").split("\nnav:", 1)[1]
    assert not re.findall(r"source \d{3}", nav)


def test_the_key_reference_shows_each_description_beside_its_key():
    """At 1,280 px the description, the table's last of eight columns, was scrolled out of sight."""
    text = (REPO / "docs" / "cell-file-reference.md").read_text(encoding="utf-8")
    heads = [line for line in text.splitlines() if line.startswith("| key |")]
    assert heads and all(h.split("|")[2].strip() == "description" for h in heads)
