"""Program files given to run, check and verify are read as cell files are: a regular file only (a FIFO or a device is
refused at once), within a size bound and a bound on any one line; --step-limit is bounded. Each refusal: one
message naming the file, exit 2."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.model.cell import EXAMPLES_DIR

LASER = EXAMPLES_DIR / "laser" / "laser_tcp.toml"
COMMANDS = {
    "run": ["run"],
    "check": ["check"],
    "verify": ["verify", str(LASER), "--target", "ur"],
}


def _refused(args: list[str], *says: str) -> None:
    """The command in a process of its own (a FIFO blocked the reader for ever): exit 2 within a minute."""
    proc = subprocess.run(
        [sys.executable, "-m", "codegen", *args], capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL
    )
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr and all(s in proc.stderr for s in says), proc.stderr


@pytest.mark.parametrize("command", COMMANDS)
def test_a_fifo_is_refused_at_once(tmp_path, command):
    fifo = tmp_path / "prog.script"
    os.mkfifo(fifo)
    _refused([*COMMANDS[command], str(fifo)], f"{fifo}: not a regular file", "give a program file")


@pytest.mark.parametrize("command", COMMANDS)
def test_a_device_behind_a_program_name_is_refused(tmp_path, command):
    """/dev/urandom read for ever (no end of file), /dev/zero filled the memory."""
    link = tmp_path / "prog.script"
    link.symlink_to("/dev/urandom")
    _refused([*COMMANDS[command], str(link)], f"{link}: not a regular file")


@pytest.mark.parametrize("command", ["run", "check"])
def test_an_over_long_line_is_named(tmp_path, command):
    program = tmp_path / "prog.script"
    program.write_text("def prog():\n  x = " + "1+" * 6000 + "1\nend\n", encoding="utf-8")
    result = CliRunner().invoke(main, [command, str(program)])
    assert result.exit_code == 2, result.output
    assert f"{program}: line 2: longer than 10,000 characters" in result.stderr


def test_a_step_limit_beyond_the_bound_is_refused(tmp_path):
    program = tmp_path / "prog.script"
    program.write_text("def prog():\n  textmsg(1)\nend\n", encoding="utf-8")
    result = CliRunner().invoke(main, ["run", str(program), "--step-limit", "9" * 30])
    assert result.exit_code == 2
    assert "'--step-limit': " + "9" * 30 + " is not within 1 .. 100,000,000" in result.stderr


@pytest.mark.parametrize(
    ("name", "text", "says"),
    [
        ("big.src", "DEF prog()\nDECL INT A[1000000000]\nA[1] = 1\nEND\n", "an array of 1,000,000,000 elements"),
        (
            "big.mod",
            "MODULE m\nPROC main()\nVAR num a{100000,100000};\na{1,1} := 1;\nENDPROC\nENDMODULE\n",
            "an array of 10,000,000,000 elements",
        ),
        (
            "frac.mod",
            "MODULE m\nPROC main()\nVAR num a{2.5};\nENDPROC\nENDMODULE\n",
            "an array's dimension must be a whole number of at least 1, got 2.5",
        ),
        (
            "zero.mod",
            "MODULE m\nPROC main()\nVAR num a{0};\nENDPROC\nENDMODULE\n",
            "an array's dimension must be a whole number of at least 1, got 0",
        ),
    ],
)
def test_arrays_are_bounded_at_declaration(tmp_path, name, text, says):
    """A billion-element KRL array or a RAPID 100000 x 100000 one ran for minutes, filling the memory, before any
    statement; RAPID's a{2.5} was an array of 2."""
    program = tmp_path / name
    program.write_text(text, encoding="utf-8")
    _refused(["run", str(program)], f"{program}:", says)


@pytest.mark.parametrize(
    ("option", "says"),
    [
        (["--input", "input_float_register_24=nan"], "--input input_float_register_24: not a finite number"),
        (["--input", "input_float_register_24=1e999"], "--input input_float_register_24: not a finite number"),
        (["--start", "1e308,0,0,0,0,0"], "each within +-3,600"),
    ],
)
def test_run_options_hold_what_a_controller_holds(tmp_path, option, says):
    """nan and 1e999 were read as numbers the program then computed with; a start joint of 1e308 deg was taken."""
    program = tmp_path / "prog.script"
    program.write_text("def prog():\n  textmsg(read_input_float_register(24))\nend\n", encoding="utf-8")
    result = CliRunner().invoke(main, ["run", str(program), *option])
    assert result.exit_code == 2, result.output
    assert says in result.stderr


def test_run_options_still_take_numbers(tmp_path):
    program = tmp_path / "prog.script"
    program.write_text("def prog():\n  textmsg(read_input_float_register(24))\nend\n", encoding="utf-8")
    result = CliRunner().invoke(main, ["run", str(program), "--input", "input_float_register_24=-2.5e1"])
    assert result.exit_code == 0, result.output
    assert "message: -25" in result.output
