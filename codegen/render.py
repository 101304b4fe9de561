"""Render a cell for each target through Jinja templates, validate, and write atomically."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from codegen import __version__, data_dir, signals, vision
from codegen.cell import Cell
from codegen.controllers import Target, get_target
from codegen.emit import Emitter, folder_name
from codegen.guard import (
    GUARD_CODES,
    NO_ANSWER,
    NO_FEEDBACK,
    NOT_AT_HOME,
    NOT_RELEASED,
    READING_RANGE_DEG,
    READING_RANGE_MM,
    UNKNOWN_STATION_TEXT,
    halt_message,
)
from codegen.kinds import get_kind, kinds
from codegen.motion import segments
from codegen.robot.emission import cell_robot, station_arm

TEMPLATES_DIR = data_dir("templates")


@dataclass(frozen=True)
class RenderedFile:
    relpath: str  # <cell>/<target>/<file>
    text: str


def _env():
    import jinja2  # imported where used: `codegen correct` must not pay for it

    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(TEMPLATES_DIR)),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
    )


def _station_context(cell: Cell, station, target: Target, emitter: Emitter) -> dict:
    origin = f"station[{station.id}] {station.name!r}"
    taught = len(station.poses)
    segs = segments(cell.motion, taught, station.retreat is not None)
    poses = [
        {
            "name": emitter.comment(pose.name),
            "ident": emitter.identifier(f"p{station.id}_", pose.name, f"{origin} pose {pose.name!r}")
            if i < taught
            else emitter.identifier(f"r{station.id}_", station.poses[-1].name, f"{origin} retreat"),
            "numbers": emitter.pose(pose),
            "motion": "joint" if i == 0 else "linear",
            "retreat": i == taught,
            # the segment into the pose ([cell.motion]): the work speed or the travel speed, a blend or a stop
            "slow": seg.exact or i == taught,
            "blend": seg.zone_mm > 0,
            "exact": seg.exact,
        }
        for i, (pose, seg) in enumerate(zip(station.path, segs, strict=True))
    ]
    arm = station_arm(cell, target, station)  # the kind's arm poses; the station's poses are the last ones
    for pose, config in zip(poses, arm[len(arm) - len(poses) :] if arm else [None] * len(poses), strict=True):
        pose["config"] = config
    kind = get_kind(station.kind)
    own = kind.station_context(cell, station, target, emitter)
    shared = {
        "kind": station.kind,
        "id": station.id,
        "name": emitter.comment(station.name),
        "ident": emitter.identifier("st_", station.name, origin),
        "poses": poses,
        "work": poses[taught - 1],
        "arm": arm,
    }
    return _merged(shared, own, f"station context of the {station.kind} kind")


def _merged(shared: dict, own: dict, what: str) -> dict:
    """A kind's template variables beside the shared ones; a name in both is a generator bug."""
    clash = sorted(shared.keys() & own.keys())
    if clash:
        raise RuntimeError(f"{what} redefines {', '.join(clash)}")
    return {**shared, **own}


def context(cell: Cell, target: Target) -> dict:
    emitter = Emitter(target)
    number = emitter.number
    stations = [_station_context(cell, station, target, emitter) for station in cell.stations]
    used = {station.kind for station in cell.stations}
    out = {
        "version": __version__,
        "cell": {
            "name": cell.name,
            "ident": emitter.identifier("", cell.name, "cell name"),
            "file": file_stem(cell, target),
            "comment": emitter.comment(cell.name),
            "source": emitter.comment(Path(cell.source).name),
            "sha256": cell.sha256,
            "angle_sign": str(cell.angle_sign),
            "max_shift_sq": number(cell.limits.max_shift_mm**2, 6),
            "max_rotation": number(cell.limits.max_rotation_deg, 6),
            "max_shift_text": f"{cell.limits.max_shift_mm:g}",
            "max_rotation_text": f"{cell.limits.max_rotation_deg:g}",
        },
        "codes": GUARD_CODES,
        "reading_range": {
            "mm": number(READING_RANGE_MM, 1),
            "deg": number(READING_RANGE_DEG, 1),
            "mm_whole": number(READING_RANGE_MM, 0),
            "deg_whole": number(READING_RANGE_DEG, 0),
        },
        "stations": stations,
        "kinds_used": [name for name in kinds() if name in used],
        "unknown_station_text": emitter.string(UNKNOWN_STATION_TEXT),
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
        "vision": {
            "read": vision.READ,
            "photo": vision.PHOTO,
            "poll_s": number(vision.POLL_S, 2),
            "polls": vision.polls(cell.vision),
            "timeout_s": number(cell.vision.timeout_s, 3),
            "timeout_text": f"{cell.vision.timeout_s:g}",
            "no_answer": emitter.string(halt_message(cell, NO_ANSWER, None, 0)),
        },
        "target": target,
        "robot": cell_robot(cell, target),
    }
    for kind in kinds().values():
        out = _merged(out, kind.cell_context(cell, target, emitter), f"cell context of the {kind.name} kind")
    return out


def cell_dir(cell: Cell) -> str:
    """The folder of a cell under generated/: its name in [a-z0-9_] (target-independent)."""
    return folder_name(cell.name)


def file_stem(cell: Cell, target: Target) -> str:
    """What "{cell}" becomes in the file names: the program's identifier, lower case."""
    return Emitter(target).identifier("", cell.name, "cell name").lower()


def output_names(cell: Cell, target: Target) -> list[str]:
    """File names; the program name inside must match them (some controllers), so both come from one identifier."""
    return [name.format(cell=file_stem(cell, target)) for name in target.files]


def render(cell: Cell, targets: list[str] | None = None) -> list[RenderedFile]:
    """Every file of every requested target, rendered in memory (nothing written)."""
    env = _env()
    out = []
    for name in targets or list(cell.targets):
        target = get_target(name)
        ctx = context(cell, target)
        # Each kind's partial templates/<target>/kinds/<kind>.j2 is a set of macros (interface,
        # constants, data, helpers, start, station) that the controller's program template calls.
        partials = {kind: env.get_template(f"{name}/kinds/{kind}.j2").make_module(ctx) for kind in kinds()}
        ctx = {**ctx, "partial": partials, "used": [partials[kind] for kind in ctx["kinds_used"]]}
        # the file "{cell}_node.script" comes from the template "program_node.script.j2"
        for pattern, file_name in zip(target.files, output_names(cell, target), strict=True):
            if not cell.stations:
                break  # a cell of pallets alone: no vision program
            text = env.get_template(f"{name}/{pattern.format(cell='program')}.j2").render(ctx)
            out.append(RenderedFile(f"{cell_dir(cell)}/{name}/{file_name}", text))
        out.extend(_pallet_files(env, cell, target, ctx))
        out.extend(_conveyor_files(env, cell, target, ctx))
        out.extend(_laser_files(env, cell, target, ctx))
    paths = [f.relpath for f in out]
    if len(set(paths)) != len(paths):  # a generator bug: one file would silently replace another
        raise RuntimeError(f"two files render to {sorted(p for p in paths if paths.count(p) > 1)[0]}")
    return out


def _conveyor_files(env, cell: Cell, target: Target, ctx: dict) -> list[RenderedFile]:
    """The pick-from-belt program of a cell with [conveyor.pick]: "cnv_<cell>.script" from the template
    "conveyor.script.j2" (the files' pattern "{conveyor}.script")."""
    from codegen.conveyor.program import conveyor_context, conveyor_file_names, picks_on

    if not picks_on(cell, target):
        return []
    cctx = {**ctx, "conveyor": conveyor_context(cell, target, Emitter(target))}
    names = conveyor_file_names(cell, target)
    return [
        RenderedFile(
            f"{cell_dir(cell)}/{target.name}/{name}",
            env.get_template(f"{target.name}/{pattern.format(conveyor='conveyor')}.j2").render(cctx),
        )
        for pattern, name in zip(target.program["conveyor_files"], names, strict=True)
    ]


def _laser_files(env, cell: Cell, target: Target, ctx: dict) -> list[RenderedFile]:
    """Source 003's automatic TCP program of a cell with [laser]: "tcp_<cell>.mod" from "laser.mod.j2"."""
    from codegen.laser.program import calibrates_on, laser_context, laser_file_names

    if not calibrates_on(cell, target):
        return []
    lctx = {**ctx, "laser": laser_context(cell, target, Emitter(target))}
    return [
        RenderedFile(
            f"{cell_dir(cell)}/{target.name}/{name}",
            env.get_template(f"{target.name}/{pattern.format(laser='laser')}.j2").render(lctx),
        )
        for pattern, name in zip(target.program["laser_files"], laser_file_names(cell, target), strict=True)
    ]


def _pallet_files(env, cell: Cell, target: Target, ctx: dict) -> list[RenderedFile]:
    """Each [[pallet]]'s stacking program: "{pallet}.src" from the template "pallet.src.j2"."""
    from codegen.pallet.program import check_level, pallet_context, pallet_file_names, pallet_identifiers

    out = []
    emitter = Emitter(target)
    for index, (pallet, ident) in enumerate(zip(cell.pallets, pallet_identifiers(cell, target), strict=True)):
        check_level(pallet, target)
        pctx = {**ctx, "pallet": pallet_context(cell, pallet, index, ident, target, emitter)}
        names = pallet_file_names(target, pctx["pallet"]["ident"])
        for pattern, file_name in zip(target.program["pallet_files"], names, strict=True):
            text = env.get_template(f"{target.name}/{pattern.format(pallet='pallet')}.j2").render(pctx)
            out.append(RenderedFile(f"{cell_dir(cell)}/{target.name}/{file_name}", text))
    return out
