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


@pytest.mark.slow
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
            (aside,) = out.glob(f".{CELL}.codegen-old-*")
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


@pytest.mark.slow
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


@pytest.mark.slow
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


@pytest.mark.slow
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


def _one_message(result, *says: str) -> None:
    assert result.exit_code == 2, result.output
    assert isinstance(result.exception, SystemExit) and "Traceback" not in result.output
    errors = [line for line in result.output.splitlines() if line.strip()]
    assert len(errors) == 1 and all(s in errors[0] for s in says), result.output


def _tree(folder: Path) -> dict[str, bytes | str]:
    """Every path below `folder`: a file's bytes, a symlink's target, a folder's "/"."""
    tree = {}
    for path in sorted(folder.rglob("*")):
        name = path.relative_to(folder).as_posix()
        if path.is_symlink():
            tree[name] = "-> " + os.readlink(path)
        elif path.is_dir():
            tree[name] = "/"
        else:
            tree[name] = path.read_bytes()
    return tree


def test_a_file_where_the_cell_folder_goes_stays_and_nothing_is_written(tmp_path):
    """The exchange used to swap the new set in and move the user's file to .<cell>.new-<pid>, then report
    "cannot write": every later run failed until someone removed it."""
    out = tmp_path / "out"
    out.mkdir()
    (out / CELL).write_text("my notes")
    result = CliRunner().invoke(main, ["generate", str(DEMO), "--out", str(out)])
    _one_message(result, f"{out / CELL}: a file, where the cell's output folder goes; nothing was written")
    assert {k: v for k, v in _tree(out).items() if not k.endswith(".lock")} == {CELL: b"my notes"}


def test_a_symlink_where_the_cell_folder_goes_stays_and_its_folder_is_untouched(tmp_path):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "keep.txt").write_text("k")
    out = tmp_path / "out"
    out.mkdir()
    (out / CELL).symlink_to(mine)
    result = CliRunner().invoke(main, ["generate", str(DEMO), "--out", str(out)])
    _one_message(result, f"{out / CELL}: a symlink (to {mine}); codegen replaces the cell's folder whole")
    assert (out / CELL).is_symlink() and os.readlink(out / CELL) == str(mine)
    assert _tree(mine) == {"keep.txt": b"k"}
    assert sorted(p.name for p in out.iterdir()) == [f".{CELL}.lock", CELL]


@pytest.mark.parametrize("cell_folder", [True, False], ids=["with the cell folder", "without"])
def test_folders_that_look_like_staging_folders_are_the_users(tmp_path, cell_folder):
    """A user's .<cell>.new-backup/ was deleted and .<cell>.old-2024/ renamed into place; a run now touches only
    the folders its own journal (in the lock file) names, whatever the names beside it look like."""
    out = tmp_path / "out"
    out.mkdir()
    if cell_folder:
        _generate([str(DEMO), "--out", str(out)])
    names = [f".{CELL}.new-backup", f".{CELL}.old-2024", f".{CELL}.new-123", f".{CELL}.codegen-old-1-0123abcd"]
    for name in names:
        (out / name).mkdir()
        (out / name / "mine.txt").write_text(name)
    before = {k: v for k, v in _tree(out).items() if k.startswith(tuple(names))}
    _generate([str(DEMO), "--out", str(out)])
    assert {k: v for k, v in _tree(out).items() if k.startswith(tuple(names))} == before
    assert (out / CELL / "ur" / f"{CELL}.script").is_file()


def test_a_journal_naming_a_users_folder_in_another_form_is_not_followed(tmp_path):
    """Only the names codegen makes for this cell are acted on: a journal line naming a path, another cell's
    folder or the cell folder itself is ignored."""
    out = tmp_path / "out"
    _generate([str(DEMO), "--out", str(out)])
    (tmp_path / "precious").mkdir()
    (out / "other").mkdir()
    lock = out / f".{CELL}.lock"
    header = lock.read_text()
    lines = ["stage ../precious", "stage other", f"aside {CELL}", "stage .other.codegen-new-1-0123abcd"]
    lock.write_text(header + "".join(line + "\n" for line in lines))
    (out / ".other.codegen-new-1-0123abcd").mkdir()
    _generate([str(DEMO), "--out", str(out)])
    assert (tmp_path / "precious").is_dir() and (out / "other").is_dir()
    assert (out / ".other.codegen-new-1-0123abcd").is_dir() and lock.read_text() == header


def test_a_lock_file_that_is_not_codegens_is_refused(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / f".{CELL}.lock").write_text("my lock of something else\n")
    result = CliRunner().invoke(main, ["generate", str(DEMO), "--out", str(out)])
    _one_message(result, f"{out / f'.{CELL}.lock'}: not codegen's lock file")
    assert (out / f".{CELL}.lock").read_text() == "my lock of something else\n"
    assert sorted(p.name for p in out.iterdir()) == [f".{CELL}.lock"]


def test_a_symlinked_lock_file_is_not_written_through(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (tmp_path / "target.txt").write_text("t")
    (out / f".{CELL}.lock").symlink_to(tmp_path / "target.txt")
    result = CliRunner().invoke(main, ["generate", str(DEMO), "--out", str(out)])
    _one_message(result, "a symlink where codegen keeps its lock file; nothing was written")
    assert (tmp_path / "target.txt").read_text() == "t"


def test_an_out_folder_that_cannot_be_written_gets_one_message(tmp_path, monkeypatch):
    _generate([str(DEMO), "--out", str(tmp_path / "out")])
    before = _tree(tmp_path / "out")
    os.chmod(tmp_path / "out", 0o555)
    if os.geteuid() == 0:  # root writes anyway: make the folder refuse as it refuses everyone else
        real_mkdir = os.mkdir

        def refused(path, *a, **k):
            if Path(path).parent == tmp_path / "out":
                raise PermissionError(13, "Permission denied", str(path))
            return real_mkdir(path, *a, **k)

        monkeypatch.setattr(os, "mkdir", refused)
    try:
        result = CliRunner().invoke(main, ["generate", str(DEMO), "--out", str(tmp_path / "out")])
    finally:
        os.chmod(tmp_path / "out", 0o755)
    _one_message(result, "cannot write (Permission denied); previous output left as it was")
    assert _tree(tmp_path / "out") == before


@pytest.mark.parametrize("what", ["file", "file's child"])
def test_an_out_that_is_a_file_gets_one_message(tmp_path, what):
    (tmp_path / "f").write_text("mine")
    out = tmp_path / "f" if what == "file" else tmp_path / "f" / "sub"
    result = CliRunner().invoke(main, ["generate", str(DEMO), "--out", str(out)])
    assert result.exit_code == 2 and "Traceback" not in result.output, result.output
    assert (tmp_path / "f").read_text() == "mine" and sorted(p.name for p in tmp_path.iterdir()) == ["f"]
