"""Render a cell's programs for each target through Jinja templates: every kind's programs, checked and in memory."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from codegen import __version__, data_dir
from codegen.controllers import Target, get_target
from codegen.emit import Emitter, folder_name
from codegen.guard import NO_FEEDBACK, NOT_AT_HOME, NOT_RELEASED, halt_message
from codegen.model import io as signals
from codegen.model.cell import Cell
from codegen.protocol import ProgramPlan, kinds
from codegen.robot.emission import cell_robot

TEMPLATES_DIR = data_dir("templates")


@dataclass(frozen=True)
class RenderedFile:
    relpath: str  # <cell>/<target>/<file>
    text: str


def environment():
    """The templates' Jinja environment (StrictUndefined: a missing variable is an error, not an empty text)."""
    import jinja2  # imported where used: `codegen correct` must not pay for it

    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(TEMPLATES_DIR)),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
    )


def merged(shared: dict, own: dict, what: str) -> dict:
    """A kind's template variables beside the shared ones; a name in both is a generator bug."""
    clash = sorted(shared.keys() & own.keys())
    if clash:
        raise RuntimeError(f"{what} redefines {', '.join(clash)}")
    return {**shared, **own}


def shared_context(cell: Cell, target: Target) -> dict:
    """The template variables every program of every kind reads: the header, the cell's speeds, its signals
    ([cell.io]) and its arm and tool."""
    emitter = Emitter(target)
    number = emitter.number
    return {
        "version": __version__,
        "cell": {
            "name": cell.name,
            "ident": emitter.identifier("", cell.name, "cell name"),
            "file": file_stem(cell, target),
            "comment": emitter.comment(cell.name),
            "source": emitter.comment(Path(cell.source).name),
            "sha256": cell.sha256,
        },
        "speeds": {  # [cell.motion]
            "travel_mm_s": number(cell.motion.speed_mm_s, 1),
            "work_mm_s": number(cell.motion.work_speed_mm_s, 1),
            "travel_m_s": number(cell.motion.speed_mm_s / 1000.0, 4),
            "work_m_s": number(cell.motion.work_speed_mm_s / 1000.0, 4),
            "zone_mm": number(cell.motion.zone_mm, 1),
            "zone_m": number(cell.motion.zone_mm / 1000.0, 4),
            # a RAPID zonedata scaled from the cell's zone as the predefined zN are: 1.5 N mm, 0.15 N deg
            "zone_ori_mm": number(1.5 * cell.motion.zone_mm, 1),
            "zone_deg": number(0.15 * cell.motion.zone_mm, 2),
            "retreat_mm": f"{cell.motion.retreat_mm:g}",
            "return_home": cell.motion.return_home,
            # a program that refuses to start away from home (targets/<t>.toml restart = "at_home")
            "start_tol_deg": number(cell.motion.start_tolerance_deg, 3),
            "joint_percent": number(cell.motion.joint_speed_percent, 1),
            "start_tol_rad": number(math.radians(cell.motion.start_tolerance_deg), 6),
            "not_at_home": emitter.string(halt_message(cell, NOT_AT_HOME, None, 0)),
        },
        "io": None
        if cell.io is None or not target.program.get("signals")
        else {  # [cell.io]: the work pose's output and its feedback, as the controller names them
            "output": cell.io.output[target.name],
            "feedback": cell.io.feedback.get(target.name),
            "value": cell.io.value,
            "polls": signals.polls(cell.io),
            "poll_s": number(signals.POLL_S, 2),
            "timeout_s": number(cell.io.timeout_s, 3),
            "timeout_text": f"{cell.io.timeout_s:g}",
            "no_feedback": emitter.string(halt_message(cell, NO_FEEDBACK, None, 0)),
            "not_released": emitter.string(halt_message(cell, NOT_RELEASED, None, 0)),
        },
        "target": target,
        "robot": cell_robot(cell, target),
    }


def cell_dir(cell: Cell) -> str:
    """The folder of a cell under generated/: its name in [a-z0-9_] (target-independent)."""
    return folder_name(cell.name)


def file_stem(cell: Cell, target: Target) -> str:
    """What "{cell}" becomes in the file names: the program's identifier, lower case."""
    return Emitter(target).identifier("", cell.name, "cell name").lower()


def plans(cell: Cell, target: Target) -> list[ProgramPlan]:
    """Every program of every kind for one target, in the kinds' order."""
    return [plan for kind in kinds().values() for plan in kind.programs(cell, target)]


def render(cell: Cell, targets: list[str] | None = None) -> list[RenderedFile]:
    """Every file of every requested target, rendered in memory (nothing written)."""
    env = environment()
    out = []
    for name in targets or list(cell.targets):
        target = get_target(name)
        shared = shared_context(cell, target)
        for plan in plans(cell, target):
            ctx = merged(shared, plan.context, f"the context of the {plan.kind} kind")
            for f in plan.files:
                out.append(RenderedFile(f"{cell_dir(cell)}/{name}/{f.name}", env.get_template(f.template).render(ctx)))
    paths = [f.relpath for f in out]
    if len(set(paths)) != len(paths):  # a generator bug: one file would silently replace another
        raise RuntimeError(f"two files render to {sorted(p for p in paths if paths.count(p) > 1)[0]}")
    return out


def output_names(cell: Cell, target: Target) -> list[str]:
    """Every file name the cell's programs have for a target (the program files first, each with its own)."""
    return [f.name for plan in plans(cell, target) for f in plan.files]
