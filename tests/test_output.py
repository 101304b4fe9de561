"""`codegen generate` replaces a cell's programs whole: killed at any step, run twice at once, mixed sets named."""

from __future__ import annotations

import fcntl
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main

REPO = Path(__file__).resolve().parents[1]
DEMO = REPO / "codegen" / "examples" / "agv_machine_tending.toml"
CELL = "agv_machine_tending"


def _killed_generate(limit: int, mode: str, args: list[str]) -> int:
    """Run `codegen generate` in a forked process (a real process: its own files, locks and death)
    that kills itself with SIGKILL, as a power cut or a CI timeout would, at its `limit`-th
    file-system step: a folder made, a file written or flushed, a rename, the exchange, a copy, a
    removal. Returns the exit status (0: it completed, no step was that far)."""
    pid = os.fork()
    if pid == 0:  # the child: count the steps, die at the chosen one
        code = 1
        try:
            from codegen import output

            steps = [0]

            def counted(fn):
                def step(*a, **k):
                    steps[0] += 1
                    if steps[0] == limit:
                        os.kill(os.getpid(), signal.SIGKILL)
                    return fn(*a, **k)

                return step

            for owner, name in [
                (os, "mkdir"),
                (os, "fsync"),
                (os, "rename"),
                (os, "symlink"),
                (shutil, "rmtree"),
                (shutil, "copy2"),
                (shutil, "copytree"),
                (output, "_exchange"),
                (output, "_write"),
            ]:
                setattr(owner, name, counted(getattr(owner, name)))
            if mode == "no-exchange":
                output._exchange = lambda a, b: False
            result = CliRunner().invoke(main, ["generate", *args])
            code = result.exit_code
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    return -os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status)


def _small_cells(tmp_path: Path) -> tuple[Path, Path]:
    """The demo cell's first two stations (quick to render), and the same with a mark moved."""
    text = DEMO.read_text()
    small = text[: text.index("[[station]]\nid = 3")]
    old, new = tmp_path / "old" / f"{CELL}.toml", tmp_path / "new" / f"{CELL}.toml"
    moved = small.replace("mark = [612.4, -285.0, 1.8]", "mark = [612.9, -285.0, 1.8]")
    for path, body in ((old, small), (new, moved)):
        path.parent.mkdir()
        path.write_text(body)
    return old, new


def _files(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def _generate(args: list[str]) -> None:
    result = CliRunner().invoke(main, ["generate", *args])
    assert result.exit_code == 0, result.output


@pytest.fixture(scope="module")
def sets(tmp_path_factory):
    """The complete old set and new set (a mark moved; only ur and kuka regenerated), the new cell
    file, and a folder holding the old set to start each run from."""
    base = tmp_path_factory.mktemp("sets")
    old_cell, new_cell = _small_cells(base)
    _generate([str(old_cell), "--out", str(base / "old_set")])
    old = _files(base / "old_set" / CELL)
    shutil.copytree(base / "old_set", base / "expected")
    _generate([str(new_cell), "--target", "ur", "--target", "kuka", "--out", str(base / "expected")])
    new = _files(base / "expected" / CELL)
    assert old != new and old.keys() == new.keys()
    return old, new, new_cell, base / "old_set"


@pytest.mark.parametrize("mode", ["exchange", "no-exchange"])
def test_a_kill_at_any_step_leaves_the_old_or_the_new_set(sets, tmp_path, mode):
    old, new, new_cell, old_set = sets
    command = [str(new_cell), "--target", "ur", "--target", "kuka"]
    outcomes, step = [], 0
    while True:
        step += 1
        out = tmp_path / f"out{step}"
        shutil.copytree(old_set, out)
        returncode = _killed_generate(step, mode, [*command, "--out", str(out)])
        folder = out / CELL
        if mode == "no-exchange" and not folder.exists():  # killed between the fallback's two renames
            (aside,) = out.glob(f".{CELL}.old-*")
            assert _files(aside) == old
            outcomes.append("aside")
        else:
            got = _files(folder)
            assert got in (old, new), f"step {step}: a mixed or partial set"
            outcomes.append("old" if got == old else "new")
        _generate([str(new_cell), "--target", "ur", "--target", "kuka", "--out", str(out)])  # the next run
        assert _files(out / CELL) == new
        assert sorted(p.name for p in out.iterdir()) == [f".{CELL}.lock", CELL], "temp folders left behind"
        if returncode == 0:
            break
        assert returncode == -signal.SIGKILL, returncode
    assert step > 15 and outcomes[0] == "old" and outcomes[-1] == "new"  # the kills covered every step


def test_random_kills_of_a_large_cell(tmp_path):
    """Kills at random moments while a 100-station cell's programs are replaced (two: every step is
    killed in turn by test_a_kill_at_any_step_leaves_the_old_or_the_new_set; the suite's five minutes)."""
    text = DEMO.read_text()
    head, one = text[: text.index("[[station]]")], text[text.index("[[station]]") : text.index("[[station]]\nid = 2")]
    big = head + "".join(one.replace("id = 1", f"id = {i}").replace("lathe_1", f"lathe_{i}") for i in range(1, 101))
    old_cell, new_cell = tmp_path / "old.toml", tmp_path / "new.toml"
    old_cell.write_text(big)
    new_cell.write_text(big.replace("mark = [612.4, -285.0, 1.8]", "mark = [612.9, -285.0, 1.8]"))
    _generate([str(old_cell), "--out", str(tmp_path / "old")])
    start = time.perf_counter()
    new_run = [sys.executable, "-m", "codegen", "generate", str(new_cell), "--out"]
    subprocess.run([*new_run, str(tmp_path / "new")], check=True, capture_output=True)
    duration = time.perf_counter() - start
    old, new = _files(tmp_path / "old" / CELL), _files(tmp_path / "new" / CELL)
    rng = random.Random(17)
    for i in range(2):
        out = tmp_path / f"kill{i}"
        shutil.copytree(tmp_path / "old", out)
        proc = subprocess.Popen([*new_run, str(out)], stdout=subprocess.DEVNULL)
        time.sleep(rng.uniform(0.5, 1.0) * duration)
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        assert _files(out / CELL) in (old, new)


def test_a_second_run_while_one_writes_fails_whole(tmp_path):
    _generate([str(DEMO), "--out", str(tmp_path)])
    before = _files(tmp_path / CELL)
    fd = os.open(tmp_path / f".{CELL}.lock", os.O_RDWR)
    fcntl.flock(fd, fcntl.LOCK_EX)  # as a run that is writing holds it
    try:
        result = CliRunner().invoke(main, ["generate", str(DEMO), "--out", str(tmp_path)])
    finally:
        os.close(fd)
    assert result.exit_code == 1 and "another codegen generate is writing" in result.output
    assert _files(tmp_path / CELL) == before


def test_files_get_the_permissions_of_a_normal_write(tmp_path):
    old = os.umask(0o022)
    try:
        _generate([str(DEMO), "--out", str(tmp_path)])
    finally:
        os.umask(old)
    modes = {oct(p.stat().st_mode & 0o777) for p in (tmp_path / CELL).rglob("*.*")}
    assert modes == {"0o644"}


def test_diff_and_verify_name_a_mixed_set(sets, tmp_path):
    *_, new_cell, old_set = sets
    old_cell = old_set.parent / "old" / f"{CELL}.toml"
    _generate([str(old_cell), "--out", str(tmp_path)])
    _generate([str(new_cell), "--target", "ur", "--out", str(tmp_path)])  # ur now from another cell file
    result = CliRunner().invoke(main, ["diff", str(old_cell), "--out", str(tmp_path)])
    assert result.exit_code == 1 and "different cell files (a mixed set)" in result.output
    files = [str(tmp_path / CELL / t / f"{CELL}.{s}") for t, s in (("ur", "script"), ("abb", "mod"))]
    result = CliRunner().invoke(main, ["verify", str(old_cell), *files, "--cases", "1"])
    assert "different cell files (a mixed set)" in result.output


def test_two_real_runs_at_once_never_mix(sets, tmp_path):
    *_, new_cell, old_set = sets
    old_cell = old_set.parent / "old" / f"{CELL}.toml"
    whole = {}
    for cell in (old_cell, new_cell):
        _generate([str(cell), "--out", str(tmp_path / cell.parent.name)])
        whole[cell] = _files(tmp_path / cell.parent.name / CELL)
    for attempt in range(3):
        out = tmp_path / f"out{attempt}"
        runs = [
            subprocess.Popen(
                [sys.executable, "-m", "codegen", "generate", str(cell), "--out", str(out)],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE,
                text=True,
            )
            for cell in (old_cell, new_cell)
        ]
        results = [(run.wait(), run.stderr.read()) for run in runs]
        assert any(code == 0 for code, _ in results)
        for code, err in results:
            assert code == 0 or (code == 1 and "another codegen generate is writing" in err), err
        assert _files(out / CELL) in list(whole.values())


def test_a_symlinked_target_folder_is_replaced_not_followed(tmp_path):
    """The new set never writes or deletes through a symlink that points out of the output tree."""
    outside = tmp_path / "v"
    outside.mkdir()
    (outside / "keep.txt").write_text("k")
    (tmp_path / "out" / CELL).mkdir(parents=True)
    (tmp_path / "out" / CELL / "ur").symlink_to(outside)
    _generate([str(DEMO), "--out", str(tmp_path / "out")])
    assert (outside / "keep.txt").read_text() == "k" and sorted(p.name for p in outside.iterdir()) == ["keep.txt"]
    ur = tmp_path / "out" / CELL / "ur"
    assert not ur.is_symlink() and (ur / f"{CELL}.script").is_file()


def test_only_what_codegen_wrote_is_replaced(tmp_path):
    """A user's file in a target's folder stays (and is named), a program codegen no longer writes goes."""
    _generate([str(DEMO), "--out", str(tmp_path)])
    ur = tmp_path / CELL / "ur"
    (ur / "notes.txt").write_text("mine")
    (ur / "old_name.script").write_text("def x():\n  # generated by codegen 0.0.1\nend\n")
    result = CliRunner().invoke(main, ["generate", str(DEMO), "--out", str(tmp_path)])
    assert result.exit_code == 0
    assert (ur / "notes.txt").read_text() == "mine" and "notes.txt: not written by codegen, kept" in result.output
    assert not (ur / "old_name.script").exists()
    assert CliRunner().invoke(main, ["diff", str(DEMO), "--out", str(tmp_path)]).exit_code == 0
