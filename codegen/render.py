"""Render a cell's programs for each target through Jinja templates (every kind's), in memory; the arm's variables."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from codegen import __version__, data_dir
from codegen.controllers import Target, get_target, numbered_names
from codegen.emit import Code, Emitter, folder_name, owned
from codegen.guard import NO_FEEDBACK, NO_PART, NOT_AT_HOME, NOT_RELEASED, PART_HELD, halt_message
from codegen.model import io as signals
from codegen.model.cell import Cell
from codegen.poses import FORMAT_DECIMALS, native_values
from codegen.protocol import ProgramPlan
from codegen.world import loads

TEMPLATES_DIR = data_dir("templates")
JOINT_DECIMALS = {"deg": 4, "rad": 6}  # 1e-4 deg; 1e-6 rad = 6e-5 deg
MASS_DECIMALS = 3
# a load's inertia numbers as written: kg m2 (1 kg mm2), the principal axes' angles (deg) and quaternion; the
# verify tolerance on a load's tensor follows from them (codegen/verify/checks.py INERTIA_ABS)
INERTIA_DECIMALS, AXES_DECIMALS, AOM_DECIMALS = 6, 4, 6


@dataclass(frozen=True)
class RenderedFile:
    relpath: str  # <cell>/<target>/<file>
    text: str


class UnmarkedText(RuntimeError):
    """A template printed a value that did not pass through the emitter (a generator bug, never the cell's)."""


def _checked(value, where: str) -> Code:
    """What a template may print: text the emitter made or the generator owns (Code), a whole number; nothing
    else (a plain string could be a cell's value, a float has no fixed decimals)."""
    if isinstance(value, Code):
        return value
    if isinstance(value, int) and not isinstance(value, bool):
        return Code(str(value))
    import jinja2  # loaded already: only a template calls this

    if isinstance(value, jinja2.Undefined):  # an inline if without else: empty; a missing variable: its error
        return Code(str(value))
    shown = repr(value)
    raise UnmarkedText(
        f"{where}: the template prints {shown[:80]}{'...' if len(shown) > 80 else ''} ({type(value).__name__}), "
        "which did not pass through the emitter (codegen/emit.py)"
    )


def environment(kinds=()):
    """The templates' Jinja environment: templates/, then the folders of the kinds given that bring their own."""
    return _environment(tuple(str(k.templates) for k in kinds if k.templates))


@cache  # one per process and set of folders: it keeps the compiled templates (Jinja reloads a changed file)
def _environment(folders: tuple[str, ...]):
    """The Jinja environment over templates/ and `folders` (StrictUndefined: a missing variable is an error).
    Every `{{ }}` prints only Code (codegen/emit.py) or a whole number: the template's own text (its literals,
    what its macros return, `~` and `join` of printable parts) stays Code; any other value is an UnmarkedText
    error naming the template, so a cell's value reaches a program only through the emitter."""
    import jinja2  # imported where used: `codegen correct` must not pay for it

    from codegen.jinjadoor import marking_environment

    @jinja2.pass_context
    def finalize(context, value) -> Code:
        return _checked(value, context.name)

    @jinja2.pass_context
    def join(context, items, separator: str = Code(""), attribute=None) -> Code:
        if attribute is not None:
            items = (context.environment.getattr(item, attribute) for item in items)
        return Code(_checked(separator, context.name).join(_checked(item, context.name) for item in items))

    @jinja2.pass_context
    def upper(context, value) -> Code:
        return _checked(value, context.name).upper()

    env = marking_environment(Code, _checked)(
        loader=jinja2.FileSystemLoader([str(TEMPLATES_DIR), *folders]),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
        finalize=finalize,
    )
    env.filters.update(join=join, upper=upper)
    return env


def merged(shared: dict, own: dict, what: str) -> dict:
    """A kind's template variables beside the shared ones; a name in both is a generator bug."""
    clash = sorted(shared.keys() & own.keys())
    if clash:
        raise RuntimeError(f"{what} redefines {', '.join(clash)}")
    return {**shared, **own}


def program_emitter(cell: Cell, target: Target) -> Emitter:
    """A program's names: the generator's own reserved (Emitter), then the cell's signals ([cell.io]) every program
    of the cell may use, before the program maps any name of the cell."""
    emitter = Emitter(target)
    if cell.io is not None and target.program.get("signals"):
        for key, signal in (("output", cell.io.output), ("feedback", cell.io.feedback)):
            if signal.get(target.name) is not None:
                emitter.signal(signal[target.name], f"cell.io.{key}.{target.name}")
    return emitter


def shared_context(cell: Cell, target: Target) -> dict:
    """The template variables every program of every kind reads: the header, the cell's speeds, its signals
    ([cell.io]) and its arm and tool."""
    emitter = program_emitter(cell, target)
    number, figure = emitter.number, emitter.figure
    return {
        "version": owned(__version__),
        "cell": {
            "ident": emitter.identifier("", cell.name, "cell name"),
            "file": file_stem(cell, target),
            "comment": emitter.comment(cell.name),
            "source": emitter.comment(Path(cell.source).name),
            "sha256": emitter.comment(cell.sha256),
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
            "retreat_mm": figure(cell.motion.retreat_mm),
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
            "output": emitter.signal(cell.io.output[target.name], f"cell.io.output.{target.name}"),
            "feedback": None
            if cell.io.feedback.get(target.name) is None
            else emitter.signal(cell.io.feedback[target.name], f"cell.io.feedback.{target.name}"),
            "value": cell.io.value,
            "polls": signals.polls(cell.io),
            "poll_s": number(signals.POLL_S, 2),
            "timeout_s": number(cell.io.timeout_s, 3),
            "timeout_text": figure(cell.io.timeout_s),
            "no_feedback": emitter.string(halt_message(cell, NO_FEEDBACK, None, 0)),
            "not_released": emitter.string(halt_message(cell, NOT_RELEASED, None, 0)),
            "part_held": emitter.string(halt_message(cell, PART_HELD, None, 0)),
            "no_part": emitter.string(halt_message(cell, NO_PART, None, 0)),
        },
        "target": {"program": owned(target.program)},  # the controller's facts (targets/<t>.toml [program])
        "robot": cell_robot(cell, target, emitter),
    }


def cell_dir(cell: Cell) -> str:
    """The folder of a cell under generated/: its name in [a-z0-9_] (target-independent)."""
    return folder_name(cell.name)


def file_stem(cell: Cell, target: Target) -> str:
    """What "{cell}" becomes in the file names: the program's identifier, lower case."""
    return Emitter(target).identifier("", cell.name, "cell name").lower()


def plans(cell: Cell, target: Target, only=None) -> list[ProgramPlan]:
    """Every program of every kind (of the kinds named `only`, if given) for one target, in the kinds' order."""
    kinds = cell.kinds.items()
    return [plan for name, kind in kinds if only is None or name in only for plan in kind.writer.programs(cell, target)]


def render_plan(
    cell: Cell, target: Target, plan: ProgramPlan, env=None, shared: dict | None = None
) -> list[RenderedFile]:
    """One program's files, rendered in memory."""
    env = env or environment(cell.kinds.values())
    ctx = merged(shared or shared_context(cell, target), plan.context, f"the context of the {plan.kind} kind")
    out = []
    for f in plan.files:  # a file's own variables (e.g. which of a task's modules it is) beside the plan's
        own = merged(ctx, f.context, f"the context of {f.name}") if f.context else ctx
        out.append(
            RenderedFile(f"{cell_dir(cell)}/{target.name}/{f.name}", str(env.get_template(f.template).render(own)))
        )
    return out


def render(cell: Cell, targets: list[str] | None = None) -> list[RenderedFile]:
    """Every file of every requested target, rendered in memory (nothing written)."""
    env = environment(cell.kinds.values())
    out = []
    for name in targets or list(cell.targets):
        target = get_target(name)
        shared = shared_context(cell, target)
        for plan in plans(cell, target):
            out.extend(render_plan(cell, target, plan, env, shared))
    paths = [f.relpath for f in out]
    if len(set(paths)) != len(paths):  # a generator bug: one file would silently replace another
        raise RuntimeError(f"two files render to {sorted(p for p in paths if paths.count(p) > 1)[0]}")
    return out


def output_names(cell: Cell, target: Target) -> list[str]:
    """Every file name the cell's programs have for a target (the program files first, each with its own)."""
    return [f.name for plan in plans(cell, target) for f in plan.files]


# --- the arm's template variables ------------------------------------------------------------


def joints_literal(values, unit: str) -> list[Code]:
    scale = math.pi / 180.0 if unit == "rad" else 1.0
    return [Emitter.number(v * scale, JOINT_DECIMALS[unit]) for v in values]


def cell_robot(cell, target, emitter: Emitter) -> dict | None:
    """The arm, its home joints and the tool for one target; None when the cell gives it no arm."""
    robot = cell.robot
    if robot is None or target.name not in robot.arms:
        return None
    unit = target.program["joint_unit"]
    fmt = target.pose_format
    tool = (
        native_values(robot.tool.tcp, cell.pose_format, fmt)
        if robot.tool.tcp
        else native_values((0.0, 0.0, 0.0, 0.0, 0.0, 0.0), "xyzabc", fmt)
    )
    cog = native_values((*robot.tool.cog_mm, 0.0, 0.0, 0.0), "xyzabc", fmt)[:3]
    decimals = FORMAT_DECIMALS[fmt]
    number = emitter.number
    return {
        "model": emitter.comment(robot.arms[target.name].model),
        "home": joints_literal(robot.home[target.name], unit),
        "tool": [number(v, d) for v, d in zip(tool, decimals, strict=True)],
        "mass": number(robot.tool.mass_kg, MASS_DECIMALS),
        "cog": [number(v, d) for v, d in zip(cog, decimals[:3], strict=True)],
        "tool_given": robot.tool_given,
        "tool_data": _numbered(target, robot.tool.numbered.get(target.name)),
        "load": inertia_literal(loads.of_tool(robot.tool, robot.tool_shaped), emitter),
        "point_mass": not robot.tool_shaped,  # the header says the tool's load has no inertia
    }


def inertia_literal(load: loads.Load, emitter: Emitter) -> dict:
    """A load's inertia in the forms the controllers take it (each targets/<t>.toml cites its own): the tensor at
    the centre of gravity in the load's frame's axes (inertia: Ixx, Iyy, Izz, Ixy, Ixz, Iyz), the principal axes
    as Z-Y-X angles (abc, deg) or a quaternion (aom), and the moments about them (moments); kg m2."""
    number = emitter.number
    moments, _ = load.principal()
    zyx = load.principal_zyx()
    _, _, aom, *_ = load.principal_quaternion()
    return {
        "inertia": [number(v, INERTIA_DECIMALS) for v in load.tensor_at_cog()[2]],
        "abc": [number(zyx[k], AXES_DECIMALS) for k in "ABC"],
        "aom": [number(v, AOM_DECIMALS) for v in aom],
        "moments": [number(v, INERTIA_DECIMALS) for v in moments],
    }


def _numbered(target, number: int | None) -> dict | None:
    """The controller's numbered tool and load the program selects, or None (it declares its own)."""
    if number is None:
        return None
    tool, load = numbered_names(target.name, number)
    return owned({"tool": tool, "load": load})


LITERALS = {  # a target's configuration form -> its template variables
    "confdata": lambda value, unit: {"robconf": Code(", ".join(str(int(v)) for v in value))},
    "status_turn": lambda value, unit: {"s": Code(str(int(value[0]))), "t": Code(str(int(value[1])))},
    "joints": lambda value, unit: {"joints": joints_literal(value, unit)},
}


def configuration_literal(target, value) -> dict:
    """A configuration value (codegen/robot/config.py FORMS) as the target's template variables."""
    return LITERALS[target.configuration](value, target.program["joint_unit"])
