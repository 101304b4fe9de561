"""`codegen generate` and `codegen diff`: render every target, check, then write or compare."""

from __future__ import annotations

import difflib
from pathlib import Path

from codegen.model.cell import Cell
from codegen.output import mixed_set, replace_cell, written_by_codegen
from codegen.render import RenderedFile, cell_dir, render
from codegen.robot.taught import ReachError


class GenerateError(Exception):
    """Rendered output that fails a check; nothing has been written."""


def check_rendered(files: list[RenderedFile]) -> None:
    """Checks every program passes before any file is replaced."""
    for f in files:
        if not f.text.isascii():
            raise GenerateError(f"{f.relpath}: non-ASCII output")
        if not f.text.endswith("\n"):
            raise GenerateError(f"{f.relpath}: no final newline")
        from codegen.dialects import check_program  # lark: loaded only when generating

        try:
            check_program(f.relpath, f.text)
        except Exception as exc:  # a generator bug, reported with the file and position
            raise GenerateError(f"{f.relpath}: generated program does not parse: {exc}") from exc


def check_envelope(cell: Cell, targets: list[str] | None) -> list:
    """Each kind's reach proof for every requested target with an arm (the stations' correction regions, a
    stack's full cycle, a belt's window, ...): each target's margins, or a GenerateError naming the pose."""
    names = list(targets or cell.targets)
    try:
        return [m for kind in cell.kinds.values() for m in kind.writer.reach(cell, names)]
    except ReachError as exc:
        raise GenerateError(str(exc)) from None


_PROVEN: dict = {}  # (the cell file's sha256, path, targets) -> the proof's least clearances (one file, one proof)


def check_clearance(cell: Cell, targets: list[str] | None) -> list:
    """Every move each kind plans on every requested target's arm, swept among the cell's solids (codegen/world/):
    the least clearance per program, or a GenerateError naming the move, the body, the solid and the distance."""
    if cell.robot is None:
        return []
    names = list(targets or cell.targets)
    key = (cell.sha256, cell.source, tuple(names)) if cell.sha256 else None
    if key is not None and key in _PROVEN:
        return _PROVEN[key]
    from codegen.world.proof import ClearanceError  # coal: loaded only when proving

    least = []
    for target in (t for t in names if t in cell.robot.arms):
        try:
            least += _proven(cell, target)
        except (ClearanceError, ReachError, ValueError) as exc:  # a path a kind plans only for the proof may not reach
            raise GenerateError(str(exc) + _other_home(cell, target)) from None
    if key is not None:
        _PROVEN[key] = least
    return least


def clears(cell: Cell) -> None:
    """A calibration's --write: the edited cell still generates (every move clears its solids), else ReachError with
    generate's refusal."""
    try:
        check_clearance(cell, None)
    except GenerateError as exc:
        raise ReachError(str(exc)) from None


def _proven(cell: Cell, target: str) -> list:
    """Each kind's paths on the target proven clear, kind by kind (those its plan proved already, as it proved them;
    the others kept by the value of what the proof reads: codegen/world/kept.py)."""
    from codegen.world.kept import proven

    least = []
    for kind in cell.kinds.values():
        done = kind.scene.proven(cell, target)
        least += done if done is not None else proven(cell, kind.scene.paths(cell, [target]))
    return least


def _other_home(cell: Cell, target: str) -> str:
    """Where the home turned half a turn about axis 1 passes the reach proof and clears every move: what to set
    (the refusal names the home in use and that one); '' where none does."""
    from dataclasses import replace

    from codegen.robot.posture import turned_homes
    from codegen.world.proof import ClearanceError

    robot = cell.robot
    for home in turned_homes(robot.arms[target], robot.home[target], robot.margins.joint_deg):
        turned = replace(cell, robot=replace(robot, home={**robot.home, target: tuple(float(v) for v in home)}))
        try:
            for kind in turned.kinds.values():
                kind.writer.reach(turned, [target])
            _proven(turned, target)
        except (ReachError, ClearanceError, ValueError):
            continue
        now = ", ".join(f"{v:g}" for v in robot.home[target])
        fix = ", ".join(f"{v:g}" for v in home)
        return (
            f". The home [cell.robot.home] {target} = [{now}] puts the arm in this posture; from the home turned half "
            f"a turn about axis 1, {target} = [{fix}], every move clears: set it in [cell.robot.home]"
        )
    return ""


def generate(cell: Cell, targets: list[str] | None, out_dir: Path) -> tuple[list[Path], list[str], list]:
    """Check the envelope and the clearance, render, check, then replace the cell's output folder whole
    (codegen.output): the regenerated targets' programs are the new ones, everything codegen did not write stays.
    Returns the written paths, what was left alone and each target's margins."""
    envelopes = check_envelope(cell, targets)
    check_clearance(cell, targets)
    files = render(cell, targets)
    check_rendered(files)
    folder = cell_dir(cell)
    below = {f.relpath.split("/", 1)[1]: f.text for f in files}
    written, left_alone = replace_cell(out_dir, folder, below, list(targets or cell.targets))
    return written, left_alone, envelopes


def mixed_stamps(paths: list[Path]) -> str | None:
    """A message when the given generated files name different cell files in their headers."""
    named = []
    for path in paths:
        try:
            named.append((str(path), path.read_text(encoding="utf-8", errors="replace")[:2000]))
        except OSError:
            continue
    return mixed_set(named)


def diff(cell: Cell, out_dir: Path) -> str:
    """Unified diff from the files in out_dir to fresh output ('' when identical)."""
    files = render(cell)
    chunks = []
    produced = set()
    for f in files:
        path = out_dir / f.relpath
        produced.add(path)
        old = path.read_text(encoding="utf-8") if path.exists() else ""
        if old != f.text:
            chunks.extend(
                difflib.unified_diff(
                    old.splitlines(keepends=True),
                    f.text.splitlines(keepends=True),
                    fromfile=str(path) if path.exists() else "/dev/null",
                    tofile=f"{path} (fresh)",
                )
            )
    for target in cell.targets:
        folder = out_dir / cell_dir(cell) / target
        for extra in sorted(folder.glob("*")):
            if extra.is_file() and not extra.is_symlink() and extra not in produced and written_by_codegen(extra):
                chunks.append(f"Only in {folder}: {extra.name} (not generated any more)\n")
    mixed = mixed_stamps(sorted(p for p in produced if p.exists()))
    if mixed:
        chunks.insert(0, f"{out_dir / cell_dir(cell)}: {mixed}\n")
    return "".join(chunks)
