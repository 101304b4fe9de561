"""The three calibrate commands read their CSV one way: bad files, huge files, pipes and odd numbers get one message."""

from __future__ import annotations

import json
import os
import threading
import time
import warnings

import numpy as np
import pytest
from click.testing import CliRunner
from test_calibrate_tcp import TCP, touch, write_csv

from codegen.cli import main
from codegen.csvfile import MAX_ROWS, number, whole

# each command's header and one good row
COMMANDS = {
    "handeye": ("u,v,x,y", "150,100,5.1,-3.2"),
    "conveyor": ("x,y,z,count,role", "0,0,0,100,belt"),
    "tcp": ("x,y,z,a,b,c", "650,120,266,0,0,180"),
}
OTHER_ROW = {"handeye": "600,100,14.1,-3.5", "conveyor": "500,0,0,4100,belt", "tcp": "650,120,266,0,30,180"}


def calibrate(command: str, path, *extra):
    return CliRunner().invoke(main, ["calibrate", command, str(path), *map(str, extra)])


def refused(result, *says: str) -> None:
    """Exit 2, one message line saying each of `says`, no traceback."""
    assert result.exit_code == 2, (result.exit_code, result.output)
    assert "Traceback" not in result.output and isinstance(result.exception, SystemExit), result.exception
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert len(lines) == 1, result.output
    for text in says:
        assert text in lines[0], result.output


@pytest.mark.parametrize("command", COMMANDS)
def test_a_huge_field_names_its_line(tmp_path, command):
    header, good = COMMANDS[command]
    path = tmp_path / "big.csv"
    path.write_text(f"{header}\n{good}\n1{'0' * 200_000},2,3,4\n")
    refused(calibrate(command, path), "big.csv:3:", "characters; at most 1,000")


@pytest.mark.parametrize("command", COMMANDS)
@pytest.mark.parametrize(
    ("encoding", "line"),
    [("latin-1", 3), ("utf-16", 1)],
)
def test_text_that_is_not_utf8_is_refused(tmp_path, command, encoding, line):
    header, good = COMMANDS[command]
    path = tmp_path / "enc.csv"
    path.write_bytes(f"{header}\n{good}\n{good},Grün\n".encode(encoding))
    refused(calibrate(command, path), f"enc.csv:{line}: ", "save the file as UTF-8")


@pytest.mark.parametrize("command", COMMANDS)
def test_a_byte_order_mark_is_read_past(tmp_path, command):
    """A spreadsheet's UTF-8 export starts with one: the header is still the header."""
    header, good = COMMANDS[command]
    path = tmp_path / "bom.csv"
    path.write_bytes(f"{header}\n{good}\n".encode("utf-8-sig"))
    result = calibrate(command, path)
    assert "header must be" not in result.output, result.output


@pytest.mark.parametrize("command", COMMANDS)
@pytest.mark.parametrize("bad", ["200_0", "nan", "inf", "1e400", "0x10", "\u0661\u0662"])
def test_a_number_is_written_in_decimal_digits(tmp_path, command, bad):
    """Python's float() reads '200_0' as 2000, '١٢' as 12 and 'nan' as a number: a CSV's numbers must not."""
    header, good = COMMANDS[command]
    cells = OTHER_ROW[command].split(",")
    cells[0] = bad
    path = tmp_path / "n.csv"
    path.write_text(f"{header}\n{good}\n{','.join(cells)}\n", encoding="utf-8")
    refused(calibrate(command, path), "n.csv:3: ", "number")


def test_the_number_syntax():
    assert [number(t) for t in ("1", " -2.5 ", "+.5", "3.", "1e3", "-1.5E-2")] == [1, -2.5, 0.5, 3, 1000, -0.015]
    for bad in ("", "1_0", "nan", "-inf", "1e999", "1.2.3", "e5", "0x1", "\u0661"):
        with pytest.raises(ValueError):
            number(bad)
    assert whole(" 65535 ") == 65535
    for bad in ("1_000", "1e3", "1.0", "\u0661"):
        with pytest.raises(ValueError):
            whole(bad)


@pytest.mark.parametrize("command", COMMANDS)
def test_100000_touches_are_refused_at_once(tmp_path, command):
    """calibrate tcp compared every two of 100,000 distinct touches (minutes); the file's size is bounded."""
    header, good = COMMANDS[command]
    path = tmp_path / "many.csv"
    rest = good.split(",", 1)[1]
    path.write_text(header + "\n" + "".join(f"{i * 0.05:.2f},{rest}\n" for i in range(100_000)))  # all apart
    refused(calibrate(command, path), "many.csv: larger than 1 MiB; a calibration file has at most 1,000 rows")


@pytest.mark.parametrize("command", COMMANDS)
def test_rows_beyond_the_bound_are_refused(tmp_path, command):
    header, good = COMMANDS[command]
    path = tmp_path / "many.csv"
    path.write_text(header + "\n" + "".join(f"{i}," + good.split(",", 1)[1] + "\n" for i in range(MAX_ROWS + 1)))
    refused(calibrate(command, path), f"many.csv:{MAX_ROWS + 2}: more than 1,000 rows")


def test_a_thousand_touches_fit_quickly(tmp_path):
    """The bound is one calibrate tcp answers at once: every two of 1,000 touches compared in one product."""
    rng = np.random.default_rng(3)
    rows = [touch(tuple(rng.uniform(-40.0, 40.0, 3))) for _ in range(MAX_ROWS)]
    data = json.loads(calibrate("tcp", write_csv(tmp_path, rows), "--json").output)
    assert data["points"] == MAX_ROWS and np.allclose(data["tcp"], TCP, atol=1e-3)
    assert 60.0 < data["orientation_spread_deg"] < 180.0


@pytest.mark.parametrize("command", COMMANDS)
def test_a_fifo_is_refused_not_waited_on(tmp_path, command):
    """A named pipe blocks the reader until someone writes to it. A helper writes a good file into it if the
    command waits for a writer (so the test ends either way); the command must refuse it without reading."""
    header, good = COMMANDS[command]
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    done = threading.Event()

    def writer() -> None:
        deadline = time.monotonic() + 10.0
        while not done.is_set() and time.monotonic() < deadline:
            try:
                fd = os.open(fifo, os.O_WRONLY | os.O_NONBLOCK)  # ENXIO until a reader has it open
            except OSError:
                time.sleep(0.05)
                continue
            try:
                os.write(fd, f"{header}\n{good}\n".encode())
            except OSError:
                pass
            finally:
                os.close(fd)
            return

    thread = threading.Thread(target=writer, daemon=True)
    thread.start()
    try:
        result = calibrate(command, fifo)
    finally:
        done.set()
        thread.join()
    refused(result, "pipe.csv: not a regular file")


@pytest.mark.parametrize("command", COMMANDS)
def test_a_folder_or_a_missing_file_gets_one_message(tmp_path, command):
    assert calibrate(command, tmp_path).exit_code == 2
    refused(calibrate(command, tmp_path / "none.csv"), "none.csv: cannot read: No such file or directory")


def test_handeye_values_beyond_any_camera_or_cell_are_refused(tmp_path):
    """1e300 mm: the fit overflowed to a residual of inf, a numpy warning and exit 0."""
    path = tmp_path / "p.csv"
    rows = [f"{u},{v},{u * 1e297!r},{v * 1e297!r}" for u, v in ((100, 100), (900, 100), (100, 900), (900, 900))]
    path.write_text("u,v,x,y\n" + "\n".join(rows) + "\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # numpy's overflow warnings fail the test
        result = calibrate("handeye", path)
    refused(result, "p.csv:2: ", "within +-10,000 mm")
