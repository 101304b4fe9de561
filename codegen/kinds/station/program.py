"""The cell's station program: the stations' template variables, each mode's partial, the program's files
(templates/<t>/program.*)."""

from __future__ import annotations

from pathlib import Path

from codegen import protocol
from codegen.controllers import Target
from codegen.dialects import get_dialect
from codegen.emit import EmitError, Emitter, owned
from codegen.guard import (
    CONNECTION_LOST,
    GUARD_CODES,
    NO_ANSWER,
    READING_RANGE_DEG,
    READING_RANGE_MM,
    UNKNOWN_STATION_TEXT,
    halt_message,
)
from codegen.kinds.station.keys import GRIP, RELEASE
from codegen.kinds.station.mode import mode_of, modes
from codegen.kinds.station.part import held_part, part_alone, part_load
from codegen.kinds.station.plan import check, taught_poses
from codegen.kinds.station.section import section_of, station_label, stations_of
from codegen.model import vision
from codegen.model.cell import Cell
from codegen.model.motion import segments
from codegen.protocol import ProgramFile, ProgramPlan
from codegen.reference import station_stops
from codegen.render import (
    LITERALS,
    MASS_DECIMALS,
    environment,
    file_stem,
    inertia_literal,
    joints_literal,
    merged,
    program_emitter,
    shared_context,
)
from codegen.robot.taught import ReachError, configuration


def _station_context(cell: Cell, station, target: Target, emitter: Emitter) -> dict:
    origin = station_label(cell, station)
    taught = len(station.poses)
    segs = segments(cell.motion, taught, station.retreat is not None, station_stops(station))
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
            "slow": seg.slow,
            "blend": seg.zone_mm > 0,
            "exact": seg.exact,
            # what the gripper does once the arm stands there ([station.gripper])
            "grip": i < taught and station.action(pose.name) == GRIP,
            "release": i < taught and station.action(pose.name) == RELEASE,
        }
        for i, (pose, seg) in enumerate(zip(station.path, segs, strict=True))
    ]
    arm = station_arm(cell, target, station)  # the mode's arm poses; the station's poses are the last ones
    for pose, config in zip(poses, arm[len(arm) - len(poses) :] if arm else [None] * len(poses), strict=True):
        pose["config"] = config
    own = mode_of(station).station_context(cell, station, target, emitter)
    shared = {
        "mode": station.mode,
        "id": station.id,
        "name": emitter.comment(station.name),
        "ident": emitter.identifier("st_", station.name, origin),
        "poses": poses,
        "work": poses[taught - 1],
        "arm": arm,
        # whether the gripper holds a part when the station starts (None: the gripper does nothing there)
        "holds_at_start": station.holds_at_start,
        "part_load": _part_load(cell, station, emitter),  # the load while its part is held (None: the tool's)
    }
    return merged(shared, own, f"station context of the {station.mode} mode")


def _part_load(cell, station, emitter: Emitter) -> dict | None:
    """The load while the station's part is in the gripper (kinds/station/part.py): the tool's and the part's in the
    flange frame ("load"), and the part's alone in the TCP frame ("part": a payload's frame); None: no part mass."""
    both = part_load(cell, station)
    if both is None:
        return None
    out = {}
    for key, load in (("load", both), ("part", part_alone(station.part))):
        out[key] = {
            "mass": emitter.number(load.mass, MASS_DECIMALS),
            "cog": [emitter.number(v, 4) for v in load.cog_mm],
            "cog_m": [emitter.number(v / 1000.0, 7) for v in load.cog_mm],
            **inertia_literal(load, emitter),
        }
    return out


def _held(cell, stations, emitter: Emitter) -> dict | None:
    """The load of a part held at the start where every station carries parts of one load (part.held_part): the
    station it is taken from (its id names its data) and its load; None: set once the station is known."""
    station = held_part(cell, stations)
    return None if station is None else {"id": station.id, **_part_load(cell, station, emitter)}


def station_arm(cell, target, station) -> list[dict]:
    """Each arm pose's configuration literal, in the order of the kind's arm_poses; [] without an arm.
    `named`: whether the program names the whole configuration (it holds over the correction region);
    else it names what holds (the status without the turn; the configuration with the check off)."""
    robot = cell.robot
    if robot is None or target.name not in robot.arms:
        return []
    arm = robot.arms[target.name]
    unit = target.program["joint_unit"]
    literal = LITERALS[target.configuration]
    try:
        taught, named_poses = taught_poses(cell, target.name, station)
    except ReachError as exc:  # a taught pose the arm cannot take: no configuration to write
        raise EmitError(str(exc)) from None
    return [
        {
            **literal(configuration(target.configuration, arm, pose.joints), unit),
            "named": named,
            "taught_joints": joints_literal(pose.joints, unit),  # where the arm stands at the taught pose
        }
        for pose, named in zip(taught, named_poses, strict=True)
    ]


def _channel(cell: Cell, target: Target, used: list) -> dict | None:
    """The network channel to the vision PC where the target's program opens one ([program] channel): its name
    (the configuration file's, the program's), the vision PC's address ([cell.vision]), the element paths, and
    the values each command's answer gives the program's variables: (variable, element path) by command."""
    facts = target.program.get("channel")
    if facts is None:
        return None
    names = {**target.program["inputs"], **target.program.get("photo", {})}
    reads: dict[int, list] = {vision.READ: ["station"], vision.PHOTO: []}
    for mode in used:
        for command, values in mode.answer_names.items():
            reads[command] += [v for v in values if v not in reads[command]]
    function = {"station": facts["int_read"]}  # the station id an INT, every other value a REAL
    emitter = program_emitter(cell, target)
    return {
        "reads": {
            c: owned([(names[v], facts["receive"][v], function.get(v, facts["real_read"])) for v in values])
            for c, values in reads.items()
            if values
        },
        "reals": [v for c in reads.values() for v in c if v != "station"],
        "errors": [(number, emitter.string(text)) for number, text in facts["messages"]],
        "other_error": emitter.string(facts["other_message"]),
        "not_deleted": emitter.string(facts["not_deleted"]),
        "name": file_stem(cell, target),
        "ip": emitter.comment(cell.vision.ip),  # in the program's comments
        "xml_ip": emitter.xml_text(cell.vision.ip),  # in the configuration's
        "port": cell.vision.port,
        "send": owned(facts["send"]),
        "send_root": owned(facts["send"]["request"].split("/")[0]),
        "receive": owned(facts["receive"]),
        "receive_root": owned(facts["receive"]["ack"].split("/")[0]),
    }


def program_context(cell: Cell, target: Target, kind_name: str) -> dict:
    """The station program's own variables: the guard's numbers, the stations, the vision handshake, and
    each mode's partial (templates/<t>/kinds/<kind>_<mode>.j2, a set of macros the program calls)."""
    section = section_of(cell)
    emitter = program_emitter(cell, target)
    number, figure = emitter.number, emitter.figure
    stations = [_station_context(cell, station, target, emitter) for station in section.stations]
    emitter.identifier("", cell.name, "cell name")  # the program's name: after the stations' (as its messages)
    used = {station.mode for station in section.stations}
    out = {
        "guard": {
            "angle_sign": section.angle_sign,
            "max_shift_sq": number(section.limits.max_shift_mm**2, 6),
            "max_rotation": number(section.limits.max_rotation_deg, 6),
            "max_shift_text": figure(section.limits.max_shift_mm),
            "max_rotation_text": figure(section.limits.max_rotation_deg),
        },
        "codes": owned(GUARD_CODES),
        "reading_range": {
            "mm": number(READING_RANGE_MM, 1),
            "deg": number(READING_RANGE_DEG, 1),
            "mm_whole": number(READING_RANGE_MM, 0),
            "deg_whole": number(READING_RANGE_DEG, 0),
        },
        "stations": stations,
        # a station's gripper acts: the program checks at the start what the gripper holds
        "gripping": any(s.gripper for s in section.stations),
        # a part held at the start whose load is known before the station is: set before the move home
        "held": _held(cell, section.stations, emitter),
        "modes_used": [name for name in modes() if name in used],
        "unknown_station_text": emitter.string(UNKNOWN_STATION_TEXT),
        "vision": {
            "read": vision.READ,
            "photo": vision.PHOTO,
            "poll_s": number(vision.POLL_S, 2),
            "polls": vision.polls(cell.vision),
            "timeout_s": number(cell.vision.timeout_s, 3),
            "timeout_text": figure(cell.vision.timeout_s),
            "no_answer": emitter.string(halt_message(cell, NO_ANSWER, None, 0)),
            "lost": emitter.string(halt_message(cell, CONNECTION_LOST, None, 0)),
        },
        "channel": _channel(cell, target, [modes()[name] for name in sorted(used)]),
    }
    for name, mode in modes().items():
        out = merged(out, mode.cell_context(cell, target, emitter), f"cell context of the {name} mode")
    # each mode's partial: macros (interface, constants, data, helpers, start, station) the program calls
    env = environment()
    ctx = {**shared_context(cell, target), **out}
    partials = {
        name: env.get_template(f"{target.name}/kinds/{kind_name}_{name}.j2").make_module(ctx) for name in modes()
    }
    return {**out, "partial": partials, "used": [partials[name] for name in out["modes_used"]]}


def station_program(cell: Cell, target: Target, kind_name: str) -> list[ProgramPlan]:
    """The programs of the cell's stations, from the target's `files`: each program file with its data files
    ("{cell}.src" and "{cell}.dat" from "program.src.j2" and "program.dat.j2"; a UR socket program and its
    Script-node twin "{cell}_node.script" from "program_node.script.j2" are two programs), one context."""

    stem = file_stem(cell, target)
    suffixes = get_dialect(target.dialect).suffixes
    context = program_context(cell, target, kind_name)
    plans: list[list[ProgramFile]] = []
    for pattern in target.files:
        f = ProgramFile(pattern.format(cell=stem), f"{target.name}/{pattern.format(cell='program')}.j2")
        if Path(pattern).suffix.lower() not in suffixes:  # a data list, a channel's configuration: its program's
            owner = next(p for p in plans if Path(p[0].name).stem == Path(f.name).stem)
            owner.append(f)
        else:
            plans.append([f])
    return [ProgramPlan(kind_name, Path(files[0].name).stem, tuple(files), context, i) for i, files in enumerate(plans)]


class WriterPart(protocol.Writer):
    """The station program (every station of the cell, each by its mode) and the stations' envelope proof."""

    renamed_copies = True

    def programs(self, cell, target) -> list[ProgramPlan]:
        return station_program(cell, target, self.kind.name) if stations_of(cell) else []

    def reach(self, cell, targets: list[str]) -> list:
        """Every taught pose over the correction region, within reach."""
        return check(cell, targets) if stations_of(cell) else []
