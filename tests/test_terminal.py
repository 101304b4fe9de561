"""What codegen prints carries no escape sequence, control character or bidirectional override from a cell, a program
or an argument: each is shown escaped, on a terminal and off it, in output, messages and click's own errors."""

from __future__ import annotations

import os
import pty
import subprocess
import sys

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.model.cell import EXAMPLES_DIR
from codegen.terminal import inert

LASER = EXAMPLES_DIR / "laser" / "laser_tcp.toml"
UNSAFE = ["\x1b", "\x07", "\r", "\x9b", "\x08", "\u202e", "\u2066", "\u200f", "\u061c", "\u2028", "\ufeff"]
PROGRAM = 'def prog():\n  textmsg("hi \x1b[31mred\u202e")\n  popup("x\x1b]0;title\x07\x08")\nend\n'


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        ("tabs\tand\nnewlines stay; é, 日本, ° too", "tabs\tand\nnewlines stay; é, 日本, ° too"),
        ("\x1b[2J\x1b]0;x\x07", "\\x1b[2J\\x1b]0;x\\x07"),
        ("a\rb\x08c\x7fd\x9be", "a\\rb\\x08c\\x7fd\\x9be".replace("\\r", "\\x0d")),
        ("abc\u202edef\u2066\u2069\u200e", "abc\\u202edef\\u2066\\u2069\\u200e"),
        ("tag\U000e0041", "tag\\U000e0041"),
        ("bad byte \udc80", "bad byte \\udc80"),
    ],
)
def test_inert_escapes_what_a_terminal_acts_on(text, shown):
    assert inert(text) == shown


def _clean(output: str) -> None:
    assert not [c for c in UNSAFE if c in output], repr(output)


def test_a_programs_messages_are_shown_escaped(tmp_path):
    program = tmp_path / "p.script"
    program.write_text(PROGRAM, encoding="utf-8")
    result = CliRunner().invoke(main, ["run", str(program)])
    assert result.exit_code == 0, result.output
    _clean(result.output)
    assert "hi \\x1b[31mred\\u202e" in result.output and "x\\x1b]0;title\\x07\\x08" in result.output


def test_a_cells_name_in_a_message_is_shown_escaped(tmp_path):
    cell = tmp_path / "cell.toml"
    cell.write_text(LASER.read_text().replace('"laser_tcp"', '"laser\\u001b[31m\\u202e"', 1), encoding="utf-8")
    result = CliRunner().invoke(main, ["generate", str(cell), "--target", "dtrans", "--out", str(tmp_path / "o")])
    assert result.exit_code == 2
    _clean(result.output)
    assert "not a target of cell laser\\x1b[31m\\u202e" in result.output


def test_clicks_own_errors_are_shown_escaped():
    result = CliRunner().invoke(main, ["gen\x1b[1merate\u202e"])
    assert result.exit_code == 2
    _clean(result.output)
    assert "No such command 'gen\\x1b[1merate\\u202e'" in result.output


def test_on_a_terminal_too(tmp_path):
    """The same program's run printed to a pseudo-terminal (click strips nothing there; the bytes reached it)."""
    program = tmp_path / "p.script"
    program.write_text(PROGRAM, encoding="utf-8")
    leader, follower = pty.openpty()
    proc = subprocess.Popen(
        [sys.executable, "-m", "codegen", "run", str(program)], stdout=follower, stderr=follower, stdin=follower
    )
    os.close(follower)
    chunks = []
    while True:
        try:
            chunk = os.read(leader, 65536)
        except OSError:  # the terminal closed: the process ended
            break
        if not chunk:
            break
        chunks.append(chunk)
    os.close(leader)
    assert proc.wait(timeout=120) == 0
    output = b"".join(chunks).decode("utf-8").replace("\r\n", "\n")
    _clean(output)
    assert "hi \\x1b[31mred\\u202e" in output
