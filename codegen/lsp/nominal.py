"""A generated program's nominal run against its cell: where each motion line sends the arm, and the joints."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from codegen.controllers import get_target
from codegen.poses import POSE_FORMATS


@dataclass(frozen=True)
class Move:
    file: str  # the file's name (the run's traces name files by their names)
    line: int
    kind: str
    pose: tuple[float, ...] | None  # in the target's pose format
    pose_format: str
    joints: tuple[float, ...] | None  # deg


def nominal_moves(cell_path: Path, program_path: Path) -> list[Move]:
    """The moves of the program's first nominal case (the kind's first category, from home), as verify runs it;
    the files are read from disk. Raises what loading the cell or the program raises."""
    from codegen.model.cell import load_cell
    from codegen.verify.plan import SCENARIOS
    from codegen.verify.programs import file_sources

    cell = load_cell(cell_path)
    sources, _warnings = file_sources(cell, [program_path], ())
    source = sources[0]
    kind = cell.kinds[source.kind].verify
    cases = [c for c in kind.cases(cell, source, 1, 0) if c.start == "home" and c.scenario not in SCENARIOS]
    if not cases:
        return []
    setup = kind.setup(cell, source, cases[0])
    arm = None if cell.robot is None else cell.robot.arms.get(source.target)
    program = source.load()
    from codegen.dialects.core.values import RunError

    try:
        trace = program.run(setup.inputs, **setup.run_options(arm, None))
    except RunError as exc:
        trace = getattr(exc, "trace", None)
        if trace is None:
            raise
    target = get_target(source.target)
    native = POSE_FORMATS[target.pose_format][2]
    main = Path(source.files[0].name).name
    return [
        Move(
            Path(m.file).name if m.file else main,
            m.line,
            m.kind,
            None if m.tcp2base is None else tuple(float(v) for v in native(m.tcp2base)),
            target.pose_format,
            None if m.joints is None else tuple(float(v) for v in m.joints),
        )
        for m in trace.moves
    ]
