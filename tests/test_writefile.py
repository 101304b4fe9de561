"""The files a user names for codegen's output (view --out, verify --html, schema --out) and the cell a calibration
writes: a FIFO, a device, a file of the user's, a read-only file and an over-long name refused at once (exit 2, one
message, nothing changed); a symlink to codegen's own page kept; two edits of one cell at once both land; hard links,
CRLF line ends kept or refused."""

from __future__ import annotations

import os
import stat
import threading
import time

import pytest
from click.testing import CliRunner

from codegen import writefile
from codegen.cli import main
from codegen.model.cell import EXAMPLES_DIR
from codegen.model.tables import schema_text

LASER = EXAMPLES_DIR / "laser" / "laser_tcp.toml"
TESTMAT = EXAMPLES_DIR / "pallets" / "testmat_pallet.toml"
# each command that writes a file the user names, without that file: the file's option comes last
WRITERS = {
    "view": ["view", LASER, "--target", "ur", "--out"],
    "verify --html": ["verify", TESTMAT, "--target", "ur", "--cases", "1", "--html"],
    "schema": ["schema", "--out"],
}


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def refused(result, *says: str) -> str:
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output and isinstance(result.exception, SystemExit)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and all(s in lines[0] for s in says), result.stderr
    assert "verify:" not in result.stdout  # refused before the run
    return lines[0]


@pytest.mark.parametrize("command", WRITERS)
def test_a_fifo_is_refused_at_once(tmp_path, command):
    """Writing a FIFO blocks until a reader comes (view and verify --html waited for ever, after their run)."""
    fifo = tmp_path / "page.html"
    os.mkfifo(fifo)
    start = time.monotonic()
    refused(invoke(*WRITERS[command], fifo), f"{fifo}: not a regular file (a FIFO, device or socket)")
    assert time.monotonic() - start < 60 and stat.S_ISFIFO(os.lstat(fifo).st_mode)


@pytest.mark.parametrize("command", WRITERS)
def test_a_device_is_refused(command):
    refused(invoke(*WRITERS[command], "/dev/null"), "/dev/null: not a regular file")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


@pytest.mark.parametrize("command", WRITERS)
def test_a_file_of_the_users_is_left_alone(tmp_path, command):
    """`schema --out mycell.toml` replaced the user's cell with the schema."""
    mine = tmp_path / "mycell.toml"
    mine.write_bytes(LASER.read_bytes())
    refused(invoke(*WRITERS[command], mine), f"{mine}: exists and was not written by codegen; left alone")
    assert mine.read_bytes() == LASER.read_bytes()


@pytest.mark.parametrize("command", WRITERS)
def test_a_symlink_to_a_file_of_the_users_is_left_alone(tmp_path, command):
    mine = tmp_path / "notes.txt"
    mine.write_text("my notes\n")
    link = tmp_path / "out.html"
    link.symlink_to(mine)
    refused(invoke(*WRITERS[command], link), f"{link} (a symlink to {mine}): exists and was not written by codegen")
    assert link.is_symlink() and mine.read_text() == "my notes\n"


@pytest.mark.parametrize("command", WRITERS)
def test_an_over_long_name_is_one_message(tmp_path, command):
    name = tmp_path / ("a" * 300 + ".html")
    refused(invoke(*WRITERS[command], name), "a name too long")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("command", WRITERS)
def test_a_read_only_file_of_codegens_is_refused_with_the_reason(tmp_path, command):
    """A page or schema codegen wrote, made read-only by its user (refused even when run as root)."""
    page = tmp_path / "out.html"
    page.write_text('<meta name="generator" content="codegen view 1">' + schema_text())
    os.chmod(page, 0o444)
    before = page.read_bytes()
    refused(invoke(*WRITERS[command], page), f"{page}: read-only; left as it was")
    assert page.read_bytes() == before


def test_a_symlink_to_codegens_own_schema_stays_a_symlink(tmp_path):
    """The link is the user's: the schema it names is replaced, the link kept (it was replaced by a file)."""
    real = tmp_path / "shipped" / "cell.schema.json"
    real.parent.mkdir()
    real.write_text(schema_text().replace("\"object\"", "\"objekt\"", 1))
    os.chmod(real, 0o640)
    link = tmp_path / "schema.json"
    link.symlink_to(real)
    result = invoke("schema", "--out", link)
    assert result.exit_code == 0, result.output
    assert link.is_symlink() and real.read_text() == schema_text()
    assert stat.S_IMODE(real.stat().st_mode) == 0o640
    assert sorted(p.name for p in real.parent.iterdir()) == ["cell.schema.json"]  # no temporary file left


def test_the_schema_replaces_its_own_file_and_its_reference_page(tmp_path):
    out = tmp_path / "schema.json"
    assert invoke("schema", "--out", out).exit_code == 0
    assert invoke("schema", "--out", out).exit_code == 0
    page = tmp_path / "reference.md"
    assert invoke("schema", "--markdown", "--out", page).exit_code == 0
    assert invoke("schema", "--markdown", "--out", page).exit_code == 0


def test_views_default_page_name_stays_in_the_folder(tmp_path, monkeypatch):
    """A cell named "../other/victim" wrote ../other/victim.html; the page's name is made as generate's folder."""
    cell = tmp_path / "work" / "cell.toml"
    cell.parent.mkdir()
    cell.write_text(LASER.read_text().replace('name = "laser_tcp"', 'name = "../other/victim"', 1))
    (tmp_path / "other").mkdir()
    monkeypatch.chdir(cell.parent)
    result = invoke("view", cell, "--target", "ur")
    assert result.exit_code == 0, result.output
    assert list((tmp_path / "other").iterdir()) == []
    assert [p.name for p in cell.parent.glob("*.html")] == ["other_victim.html"]


# --- a cell file edited by a calibration ----------------------------------------------------------


def _edit_adding(line: str, inside: threading.Event | None = None, wait: float = 0.0):
    def edit(text: str) -> str:
        if inside is not None:
            inside.set()
        time.sleep(wait)
        return text + line

    return edit


def test_two_edits_of_one_file_at_once_both_land(tmp_path):
    """The second edit starts while the first is between its read and its rename: without the lock and the read
    under it, the second's text was lost when the first renamed its (older) text over it."""
    cell = tmp_path / "cell.toml"
    cell.write_text("a = 1\n")
    inside = threading.Event()
    first = threading.Thread(
        target=writefile.replace_file, args=(cell, _edit_adding("b = 2\n", inside, wait=0.5))
    )
    first.start()
    assert inside.wait(10)
    writefile.replace_file(cell, _edit_adding("c = 3\n"))
    first.join()
    assert cell.read_text() == "a = 1\nb = 2\nc = 3\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cell.toml"]  # nothing left beside it


def test_a_file_with_hard_links_is_refused_and_kept(tmp_path):
    cell = tmp_path / "cell.toml"
    cell.write_text("a = 1\n")
    other = tmp_path / "backup.toml"
    os.link(cell, other)
    with pytest.raises(writefile.WriteRefused, match="has 2 hard links; replacing it would cut them"):
        writefile.replace_file(cell, _edit_adding("b = 2\n"))
    assert os.stat(cell).st_ino == os.stat(other).st_ino and cell.read_text() == "a = 1\n"


def test_crlf_line_ends_are_kept(tmp_path):
    cell = tmp_path / "cell.toml"
    cell.write_bytes(b"a = 1\r\nb = 2\r\n")
    writefile.replace_file(cell, _edit_adding("c = 3\n"))
    assert cell.read_bytes() == b"a = 1\r\nb = 2\r\nc = 3\r\n"


def test_a_read_only_cell_is_refused(tmp_path):
    cell = tmp_path / "cell.toml"
    cell.write_text("a = 1\n")
    os.chmod(cell, 0o444)
    with pytest.raises(writefile.WriteRefused, match="read-only; left as it was"):
        writefile.replace_file(cell, _edit_adding("b = 2\n"))
    assert cell.read_text() == "a = 1\n"
