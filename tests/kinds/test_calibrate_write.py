"""`calibrate ... --write CELL`: the cell file keeps its mode and its symlink, an unwritable folder gets one
message, and an edited cell that would not generate (any kind's reach) is refused, the file left as it was."""

from __future__ import annotations

import os
import signal
import stat
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from support import belt_sim
from test_calibrate_tcp import tilts, touch, write_csv
from test_handeye import grid_csv

from codegen import writefile
from codegen.cli import main
from codegen.model.cell import EXAMPLES_DIR, CellError, load_cell, replace_cell_file

BELT_CELL = EXAMPLES_DIR / "conveyor" / "belt_pick.toml"
PALLET_CELL = EXAMPLES_DIR / "pallets" / "testmat_pallet.toml"
BENCH_CELL = EXAMPLES_DIR / "thermometer_bench.toml"


def calibrate(*args):
    return CliRunner().invoke(main, ["calibrate", *map(str, args)])


def belt_touches(folder: Path, shift=(0.0, 0.0, 0.0)) -> Path:
    """The simulated belt's touches (codegen/examples/conveyor_touches.csv), moved by `shift` mm."""
    lines = belt_sim.csv_text(belt_sim.touches()).splitlines()
    rows = [lines[0]]
    for line in lines[1:]:
        cells = line.split(",")
        cells[:3] = [f"{float(v) + d:.3f}" for v, d in zip(cells[:3], shift, strict=True)]
        rows.append(",".join(cells))
    path = folder / "belt.csv"
    path.write_text("\n".join(rows) + "\n")
    return path


def tool_touches(folder: Path, length_mm: float) -> Path:
    rows = [touch(t, tcp=np.array([0.0, 0.0, length_mm])) for t in tilts(40)]
    return write_csv(folder, rows, name=f"tool{length_mm:g}.csv")


def setup(command: str, folder: Path) -> tuple[list, Path]:
    """A command that writes a cell it accepts: (its arguments but --write, the source cell)."""
    if command == "handeye":
        return ["handeye", grid_csv(folder)], BENCH_CELL
    if command == "conveyor":
        return ["conveyor", belt_touches(folder), "--counter-bits", 16, "--working-length", 1500], BELT_CELL
    return ["tcp", tool_touches(folder, 150.0)], BELT_CELL


COMMANDS = ["handeye", "conveyor", "tcp"]


def one_message(result, *says: str) -> str:
    assert result.exit_code == 2, result.output
    assert isinstance(result.exception, SystemExit) and "Traceback" not in result.output
    errors = [line for line in result.output.splitlines() if line.strip()]
    assert len(errors) == 1 and all(s in errors[0] for s in says), result.output
    return errors[0]


@pytest.mark.parametrize("command", COMMANDS)
def test_the_cell_file_keeps_its_mode(tmp_path, command):
    """The edited file was written by mkstemp (0600) and renamed over the cell: 0664 became 0600."""
    args, source = setup(command, tmp_path)
    cell = tmp_path / "cell.toml"
    cell.write_text(source.read_text())
    os.chmod(cell, 0o664)
    result = calibrate(*args, "--write", cell)
    assert result.exit_code == 0, result.output
    assert stat.S_IMODE(cell.stat().st_mode) == 0o664
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []  # no temporary file left


@pytest.mark.parametrize("command", COMMANDS)
def test_a_symlinked_cell_file_is_written_through(tmp_path, command):
    """The link stays a link and the file it names gets the calibration (the link used to become a copy)."""
    args, source = setup(command, tmp_path)
    (tmp_path / "real").mkdir()
    real = tmp_path / "real" / "cell.toml"
    real.write_text(source.read_text())
    link = tmp_path / "cell.toml"
    link.symlink_to(Path("real") / "cell.toml")
    before = real.read_text()
    result = calibrate(*args, "--write", link)
    assert result.exit_code == 0, result.output
    assert link.is_symlink() and os.readlink(link) == str(Path("real") / "cell.toml")
    assert real.read_text() != before and "codegen calibrate" in real.read_text()
    assert sorted(p.name for p in (tmp_path / "real").iterdir()) == ["cell.toml"]


@pytest.mark.parametrize("command", COMMANDS)
def test_a_folder_that_cannot_be_written_gets_one_message(tmp_path, command, monkeypatch):
    args, source = setup(command, tmp_path)
    folder = tmp_path / "locked"
    folder.mkdir()
    cell = folder / "cell.toml"
    cell.write_text(source.read_text())
    before = cell.read_bytes()
    os.chmod(folder, 0o555)
    if os.geteuid() == 0:  # root writes anyway: make the folder refuse as it refuses everyone else

        def refused(*_a, **_k):
            raise PermissionError(13, "Permission denied")

        monkeypatch.setattr(writefile, "put", refused)
    try:
        result = calibrate(*args, "--write", cell)
    finally:
        os.chmod(folder, 0o755)
    message = one_message(result, f"{cell}: ")
    assert "cannot write: Permission denied; the file was left as it was" in message or (
        f"its folder {folder} cannot be written" in message
    )
    assert cell.read_bytes() == before


@pytest.mark.parametrize("source", [PALLET_CELL, BELT_CELL], ids=["pallet", "belt"])
def test_a_tool_the_cell_cannot_take_is_not_written(tmp_path, source):
    """A 600 mm tool: the pallet's and the belt's poses are out of reach (the stations' envelope check alone was
    run, and these cells have no station: the cell was written, then failed at generate)."""
    cell = tmp_path / "cell.toml"
    cell.write_text(source.read_text())
    before = cell.read_bytes()
    result = calibrate("tcp", tool_touches(tmp_path, 600.0), "--write", cell)
    one_message(result, f"{cell}: with this tool the cell would not generate: ")
    assert cell.read_bytes() == before
    generate = CliRunner().invoke(main, ["generate", str(cell), "--out", str(tmp_path / "out")])
    assert generate.exit_code == 0, generate.output


def test_a_belt_the_arm_cannot_reach_is_not_written(tmp_path):
    """The same touches 2 m further along x: the belt's window leaves the arm's reach."""
    cell = tmp_path / "cell.toml"
    cell.write_text(BELT_CELL.read_text())
    before = cell.read_bytes()
    far = belt_touches(tmp_path, shift=(2000.0, 0.0, 0.0))
    result = calibrate("conveyor", far, "--counter-bits", 16, "--working-length", 1500, "--write", cell)
    one_message(result, f"{cell}: with this belt the cell would not generate: ")
    assert cell.read_bytes() == before


def test_a_reachable_calibration_is_written_and_generates(tmp_path):
    cell = tmp_path / "cell.toml"
    cell.write_text(PALLET_CELL.read_text())
    result = calibrate("tcp", tool_touches(tmp_path, 130.0), "--write", cell)
    assert result.exit_code == 0, result.output
    assert load_cell(cell).robot.tool.tcp[2] == pytest.approx(130.0, abs=1e-3)
    generate = CliRunner().invoke(main, ["generate", str(cell), "--out", str(tmp_path / "out")])
    assert generate.exit_code == 0, generate.output


def _killed_replace(path: Path, text: str, limit: int) -> int:
    """codegen.writefile.replace_file in a forked process that kills itself (SIGKILL, as a power cut would) at its
    `limit`-th file-system step; the exit status (0: it completed before that step)."""
    pid = os.fork()
    if pid == 0:
        code = 1
        try:
            steps = [0]

            def counted(fn):
                def step(*a, **k):
                    steps[0] += 1
                    if steps[0] == limit:
                        os.kill(os.getpid(), signal.SIGKILL)
                    return fn(*a, **k)

                return step

            for name in ["fchmod", "fsync", "replace", "open"]:
                setattr(os, name, counted(getattr(os, name)))
            writefile.replace_file(path, lambda _old: text, lambda written: None)
            code = 0
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    return -os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status)


def test_a_kill_at_any_step_leaves_the_old_file_or_the_new(tmp_path):
    old, new = "a = 1\n" * 20_000, "b = 2\n" * 30_000
    outcomes, step = [], 0
    while True:
        step += 1
        cell = tmp_path / f"cell{step}.toml"
        cell.write_text(old)
        os.chmod(cell, 0o640)
        status = _killed_replace(cell, new, step)
        got = cell.read_text()
        assert got in (old, new), f"step {step}: a half-written file"
        assert stat.S_IMODE(cell.stat().st_mode) == 0o640
        outcomes.append("new" if got == new else "old")
        if status == 0:
            break
        assert status == -signal.SIGKILL, status
    assert step > 4 and outcomes[0] == "old" and outcomes[-1] == "new", outcomes


def test_a_refused_text_leaves_the_file_and_no_temporary(tmp_path):
    cell = tmp_path / "cell.toml"
    cell.write_text("a = 1\n")

    def refuse(written: Path) -> None:
        assert written.read_text() == "a = 2\n" and written.parent == tmp_path
        raise ValueError("no")

    with pytest.raises(ValueError):
        writefile.replace_file(cell, lambda _old: "a = 2\n", refuse)
    assert cell.read_text() == "a = 1\n" and sorted(p.name for p in tmp_path.iterdir()) == ["cell.toml"]


def test_an_edited_cell_that_does_not_load_names_the_cell_file(tmp_path):
    """The edited text is checked as written to disk, under the cell file's name (not the temporary file's)."""
    cell = tmp_path / "cell.toml"
    cell.write_text(BELT_CELL.read_text())
    before = cell.read_bytes()
    with pytest.raises(CellError) as caught:
        replace_cell_file(cell, lambda text: text.replace("counter_bits = 16", "counter_bits = 13", 1))
    assert str(caught.value).startswith(f"{cell}: ") and ".tmp" not in str(caught.value)
    assert cell.read_bytes() == before and sorted(p.name for p in tmp_path.iterdir()) == ["cell.toml"]


@pytest.mark.parametrize("command", COMMANDS)
def test_a_cell_with_hard_links_or_read_only_gets_one_message(tmp_path, command):
    """A rename over a hard-linked cell cut the link (the other name kept the old text); a read-only cell was
    replaced anyway (the folder was writable)."""
    args, source = setup(command, tmp_path)
    cell = tmp_path / "cell.toml"
    cell.write_text(source.read_text())
    os.link(cell, tmp_path / "backup.toml")
    before = cell.read_bytes()
    one_message(calibrate(*args, "--write", cell), f"{cell}: has 2 hard links; replacing it would cut them")
    assert cell.read_bytes() == before and os.stat(cell).st_nlink == 2
    (tmp_path / "backup.toml").unlink()
    os.chmod(cell, 0o444)
    one_message(calibrate(*args, "--write", cell), f"{cell}: read-only; left as it was")
    assert cell.read_bytes() == before
