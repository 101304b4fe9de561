"""The cell file's robot sections: [cell.robot] (arm and home per target), [cell.tool] and a station's config."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cache

import numpy as np

from codegen.controllers import get_target, target_names
from codegen.model.loader import Loader
from codegen.model.schema import Key, Table
from codegen.model.validate import metres_hint
from codegen.poses import POSE_FORMATS
from codegen.robot.arms import Arm, ArmError, arm_from_table, catalogue, check_inside, find_arm
from codegen.robot.margins import joint_margins

TOOL_OFFSET_MAX_MM = 2000.0
TCP_MIN_MM = 1.0  # a TCP nearer the flange than this but not at it is no tool: a value given in metres
_MARGIN = {"type": "number", "unit": "deg", "low": 0.0, "high": 90.0}
WRIST_MARGIN_MIN_DEG = 0.1
# [cell.robot] without its per-target keys (robot_table() adds them): the definition the loader reads
ROBOT_KEYS = {
    "home": Key(
        "map",
        "the home joints per target (default: the arm's catalogue home)",
        unit="deg",
        values=Key("numbers", "joint positions a1..a6", unit="deg", count=6),
    ),
    # codegen's choice: room for the path between two checked readings
    "joint_margin_deg": Key(
        **_MARGIN, default=5.0, doc="every axis this far inside its limits over the correction region"
    ),
    # at axis 5 = 0 (or +-180) axes 4 and 6 turn about one line: the wrist's angles are ambiguous, so no margin
    # of 0 is accepted; a tenth of a degree is the least that keeps the taught wrist's split of axes 4 and 6
    "wrist_margin_deg": Key(
        **{**_MARGIN, "low": WRIST_MARGIN_MIN_DEG}, default=5.0, doc="the wrist axis this far from its singular angle"
    ),
}
# the programs write the mass in kg to 3 decimals (render.py MASS_DECIMALS): less than 1 g says 0
TOOL = Table(
    "The tool the arm carries: its TCP and load (needs [cell.robot]; without it the programs move the flange).",
    {
        "tcp": Key(
            "pose",
            "the TCP in the flange frame, in the cell's pose format",
            required=True,
            count=(6, 7),
            low=-TOOL_OFFSET_MAX_MM,
            high=TOOL_OFFSET_MAX_MM,
        ),
        "mass_kg": Key("number", "the tool's mass", unit="kg", low=0.001, high=1000.0, required=True),
        "cog_mm": Key(
            "numbers",
            "the centre of gravity in the flange frame",
            unit="mm",
            count=3,
            required=True,
            low=-TOOL_OFFSET_MAX_MM,
            high=TOOL_OFFSET_MAX_MM,
        ),
        "numbered": Key(
            "map",
            "the controller's numbered tool and load to select instead of declaring the tool, per target",
            names=None,
        ),
        # the tool's shape from the flange to the TCP, for the clearance of every move (docs/clearance.md)
        "radius_mm": Key(
            "number",
            "the tool as a cylinder of this radius from the flange's centre to the TCP",
            unit="mm",
            low=1.0,
            high=1000.0,
            default=25.0,
        ),
        "box_mm": Key(
            "numbers",
            "the tool as a box of this width (x) and depth (y) from the flange to the TCP, instead of a cylinder",
            unit="mm",
            count=2,
            low=1.0,
            high=2000.0,
        ),
    },
)
TOOL_MASS_MIN_KG, TOOL_MASS_MAX_KG = TOOL["mass_kg"].bounds
SHAPE_KEYS = {"radius_mm", "box_mm"}  # the tool's shape, which its inertia follows from
DEFAULT_JOINT_MARGIN_DEG = ROBOT_KEYS["joint_margin_deg"].default
DEFAULT_WRIST_MARGIN_DEG = ROBOT_KEYS["wrist_margin_deg"].default


def arm_targets() -> tuple[str, ...]:
    """The controllers that drive an arm model (configuration other than none)."""
    return tuple(t for t in target_names() if get_target(t).configuration != "none")


@cache
def robot_table() -> Table:
    """[cell.robot]: an arm per target that drives one (a catalogue name or a custom arm's table), its home and
    margins."""
    arm = Key(
        "either",
        "the arm this controller drives: a catalogue model name (codegen/robot/catalogue.toml) or a custom arm's table",
        alternatives=(Key("string", "a catalogue model", non_empty=True), Key("map", "a custom arm")),
    )
    per_target = {t: replace(arm, controllers=t) for t in arm_targets()}
    return Table(
        "The arm per target and its home (optional: without it nothing about the arm is checked).",
        {**per_target, **ROBOT_KEYS},
    )


@cache
def tool_table() -> Table:
    """[cell.tool] with its numbered tools per controller that has them."""
    numbered = {
        t: Key(
            "integer",
            f"the {t} controller's tool number",
            low=1,
            high=get_target(t).program["tool_data"]["max"],
            controllers=t,
        )
        for t in target_names()
        if get_target(t).program.get("tool_data")
    }
    key = TOOL["numbered"]
    return TOOL.merged(
        {"numbered": Key("map", key.doc, names=tuple(numbered), per_name=numbered, controllers=", ".join(numbered))}
    )


@dataclass(frozen=True)
class Tool:
    tcp: tuple[float, ...]  # the TCP in the flange frame, as written (cell pose format)
    tcp2flange: np.ndarray = field(compare=False)  # 4x4, mm
    mass_kg: float
    cog_mm: tuple[float, float, float]  # centre of gravity in the flange frame
    numbered: dict = field(default_factory=dict, compare=False)  # target -> the controller's tool number
    radius_mm: float = TOOL.default("radius_mm")  # its shape: a cylinder from the flange to the TCP
    box_mm: tuple[float, float] | None = None  # or a box of this width and depth


FLANGE = Tool((), np.eye(4), 0.0, (0.0, 0.0, 0.0))


@dataclass(frozen=True)
class Margins:
    joint_deg: float  # every axis this far inside its limits over the correction region
    wrist_deg: float  # the wrist axis this far from its singular angle


@dataclass(frozen=True)
class Robot:
    """The cell's arms (per target that drives one), their home joints and the tool."""

    arms: dict  # target name -> Arm
    home: dict  # target name -> joints deg
    tool: Tool
    tool_given: bool
    margins: Margins = Margins(DEFAULT_JOINT_MARGIN_DEG, DEFAULT_WRIST_MARGIN_DEG)
    tool_shaped: bool = False  # [cell.tool] declares radius_mm or box_mm: its inertia follows from that shape


@dataclass(frozen=True)
class PoseConfig:
    """A taught pose's configuration as the cell gives it: the target's own form or taught joints."""

    form: str  # "confdata", "status_turn" or "joints"
    value: tuple


def configuration_of(target_name: str) -> str:
    return get_target(target_name).configuration


def parse_robot(ctx, cell_table: dict, targets: tuple[str, ...], pose_format: str) -> Robot | None:
    """[cell.robot] and [cell.tool]; None when the cell names no arm (nothing about the arm is checked)."""
    tool, tool_given = FLANGE, False
    if "tool" in cell_table:
        tool, tool_given = _parse_tool(ctx, ctx.table(cell_table, "tool", "cell.tool"), pose_format), True
    if "robot" not in cell_table:
        if tool_given:
            ctx.fail("cell.tool", "a tool needs [cell.robot]: the arm per target that carries it")
        return None
    table = ctx.table(cell_table, "robot", "cell.robot")
    with_arm = [t for t in targets if configuration_of(t) != "none"]
    allowed = {*with_arm, *ROBOT_KEYS}
    for key in sorted(set(table) - allowed):
        if key in targets:
            ctx.fail(f"cell.robot.{key}", f"the {key} target drives no arm model (no robot in its language)")
        ctx.fail(f"cell.robot.{key}", f"unknown key; allowed: {', '.join(sorted(allowed))}")
    arms: dict[str, Arm] = {}
    for target in with_arm:
        path = f"cell.robot.{target}"
        value = ctx.require(table, target, path)
        arms[target] = _arm(ctx, value, path, target)
    home_table = table.get("home", {})
    if not isinstance(home_table, dict):
        ctx.fail("cell.robot.home", "expected a table of joint positions per target")
    home = {}
    for key in sorted(set(home_table) - set(arms)):
        ctx.fail(f"cell.robot.home.{key}", f"no arm for this target; allowed: {', '.join(arms)}")
    for target, arm in arms.items():
        if target in home_table:
            path = f"cell.robot.home.{target}"
            joints = ctx.numbers(home_table[target], 6, path)
            try:
                check_inside(joints, arm.limits_deg, path)
            except ArmError as exc:
                ctx.fail(*str(exc).split(": ", 1))
            home[target] = joints
        else:
            home[target] = arm.home_deg
    if tool_given:
        _check_payload(ctx, tool, arms, table)
        _check_length(ctx, tool, arms, pose_format)
    margins = Margins(
        _margin(ctx, table, "joint_margin_deg", DEFAULT_JOINT_MARGIN_DEG),
        _margin(ctx, table, "wrist_margin_deg", DEFAULT_WRIST_MARGIN_DEG),
    )
    for target in sorted(set(home_table) & set(arms)):
        _home_off_the_limits(ctx, home[target], arms[target], margins.joint_deg, f"cell.robot.home.{target}")
    if not tool_given:
        ctx.warnings.append(f"{ctx.source}: cell.tool: not given: the programs move the flange (no TCP, no payload)")
    shaped = tool_given and bool(SHAPE_KEYS & set(cell_table["tool"])) and bool(np.any(tool.tcp2flange[:3, 3]))
    if tool_given and not shaped:
        ctx.warnings.append(
            f"{ctx.source}: cell.tool: no shape (radius_mm or box_mm, and a TCP away from the flange): its load is "
            "a point mass at cog_mm (no inertia), as the programs' headers say"
        )
    return Robot(arms, home, tool, tool_given, margins, shaped)


def _home_off_the_limits(ctx, joints, arm, margin_deg: float, path: str) -> None:
    """A home the cell gives keeps the joint margin every taught pose keeps: the programs start and end there, and a
    home at a limit leaves the way home no room (the controller stops the arm on its soft limit)."""
    per_axis = joint_margins(arm, joints)
    for i, (q, (low, high)) in enumerate(zip(joints, arm.limits_deg, strict=True)):
        if not per_axis[i] >= margin_deg:
            ctx.fail(
                f"{path}[{i}]",
                f"axis {i + 1} at {q:g} deg is within {margin_deg:g} deg (cell.robot.joint_margin_deg) of its limits "
                f"[{low:g}, {high:g}] on the {arm.model}",
            )


def _check_payload(ctx, tool: Tool, arms: dict, table: dict) -> None:
    """The tool within each arm's payload (the catalogue's from the vendor's data sheet, or the custom arm's
    payload_kg): the part it carries comes on top, so a heavier tool can never work."""
    for target, arm in arms.items():
        if arm.payload_kg is not None and tool.mass_kg > arm.payload_kg:
            where = "its table" if isinstance(table[target], dict) else "its data sheet, codegen/robot/catalogue.toml"
            ctx.fail(
                "cell.tool.mass_kg",
                f"{tool.mass_kg:g} kg is more than the {arm.model}'s payload of {arm.payload_kg:g} kg "
                f"(cell.robot.{target}, {where}): the arm cannot carry the tool, let alone a part",
            )


def _check_length(ctx, tool: Tool, arms: dict, pose_format: str) -> None:
    """A TCP farther from the flange than an arm reaches is a length in another unit, not a tool (a UR cell's
    metres taken for mm: 1.8 for 1.8 mm is 1.8 m)."""
    length_mm = float(np.linalg.norm(tool.tcp2flange[:3, 3]))
    for target, arm in arms.items():
        if arm.reach_mm is not None and length_mm > arm.reach_mm:
            unit = f' (pose_format = "{pose_format}" takes {POSE_FORMATS[pose_format][3]})'
            ctx.fail(
                "cell.tool.tcp",
                f"the TCP is {length_mm:,.0f} mm from the flange, longer than the {arm.model}'s reach of "
                f"{arm.reach_mm:,.0f} mm (cell.robot.{target}): a value in another unit?{unit}",
            )


def check_carried(ctx, robot: Robot | None, mass_kg: float, path: str) -> None:
    """What the tool carries (mass_kg, the key at `path`) and the tool together within each arm's payload."""
    if robot is None:
        return
    tool_kg = robot.tool.mass_kg if robot.tool_given else 0.0
    for target, arm in robot.arms.items():
        if arm.payload_kg is not None and tool_kg + mass_kg > arm.payload_kg:
            ctx.fail(
                path,
                f"{mass_kg:g} kg carried by a {tool_kg:g} kg tool is more than the {arm.model}'s payload of "
                f"{arm.payload_kg:g} kg (cell.robot.{target}): the arm cannot carry it",
            )


def _margin(ctx, table: dict, key: str, default: float) -> float:
    if key not in table:
        return default
    value = ctx.number(table, key, f"cell.robot.{key}")
    if not ROBOT_KEYS[key].contains(value):
        ctx.fail(f"cell.robot.{key}", f"expected degrees in {ROBOT_KEYS[key].range_text()}, got {value:g}")
    return value


def _arm(ctx, value, path: str, target: str) -> Arm:
    if isinstance(value, str):
        arm = find_arm(value)
        if arm is None:
            vendor = get_target(target).vendor
            ctx.fail(
                path,
                f"unknown arm {value!r}; the catalogue's {vendor} arms: "
                f"{', '.join(n for n, a in catalogue().items() if a.vendor == vendor)}; another arm is a table "
                "{ model, family, params, limits_deg, home_deg } with the catalogue's parameters (docs/arm.md)",
            )
    elif isinstance(value, dict):
        try:
            arm = arm_from_table({"vendor": get_target(target).vendor, **value}, path)
        except ArmError as exc:
            ctx.fail(*str(exc).split(": ", 1))
    else:
        ctx.fail(path, "expected a catalogue model name or a table describing a custom arm")
    vendor = get_target(target).vendor
    if arm.vendor != vendor:
        ctx.fail(path, f"{arm.model} is a {arm.vendor} arm; the {target} controller drives {vendor} arms")
    return arm


def _parse_tool(ctx, table: dict, pose_format: str) -> Tool:
    ctx.no_unknown(table, TOOL.allowed, "cell.tool")
    count, to_matrix = POSE_FORMATS[pose_format][0], POSE_FORMATS[pose_format][1]
    tcp = ctx.orientation(
        ctx.numbers(ctx.require(table, "tcp", "cell.tool.tcp"), count, "cell.tool.tcp"), "cell.tool.tcp", pose_format
    )
    if pose_format == "abb":
        tcp = ctx.normalise_quaternion(tcp, "cell.tool.tcp")
    scale = 1000.0 if pose_format == "ur" else 1.0
    reach = max(abs(v) for v in tcp[:3])
    if reach * scale > TOOL_OFFSET_MAX_MM:
        hint = metres_hint(pose_format)
        ctx.fail("cell.tool.tcp", f"the TCP must be within {TOOL_OFFSET_MAX_MM:g} mm of the flange{hint}")
    if pose_format != "ur" and 0.0 < reach < TCP_MIN_MM:
        ctx.fail(
            "cell.tool.tcp",
            f"the TCP is {reach:g} mm from the flange: given in metres? This cell's poses are mm (pose_format = "
            f'"{pose_format}"): {reach:g} m is {reach * 1000.0:g} mm',
        )
    mass = ctx.number(table, "mass_kg", "cell.tool.mass_kg")
    if not TOOL_MASS_MIN_KG <= mass <= TOOL_MASS_MAX_KG:
        ctx.fail(
            "cell.tool.mass_kg",
            f"expected a mass in [{TOOL_MASS_MIN_KG:g}, {TOOL_MASS_MAX_KG:g}] kg (a moving tool has mass; the "
            "programs write it to 1 g)",
        )
    cog = ctx.numbers(ctx.require(table, "cog_mm", "cell.tool.cog_mm"), 3, "cell.tool.cog_mm")
    if max(abs(v) for v in cog) > TOOL_OFFSET_MAX_MM:
        ctx.fail("cell.tool.cog_mm", f"the centre of gravity must be within {TOOL_OFFSET_MAX_MM:g} mm of the flange")
    cog_reach = max(abs(v) for v in cog)
    if 0.0 < cog_reach < TCP_MIN_MM < reach * scale:  # the tool reaches out, its mass a hair off the flange
        ctx.fail(
            "cell.tool.cog_mm",
            f"the centre of gravity is {cog_reach:g} mm from the flange, the TCP {reach * scale:g} mm: given in "
            f"metres? cog_mm is mm in the flange frame: {cog_reach:g} m is {cog_reach * 1000.0:g} mm",
        )
    matrix = to_matrix(tcp)
    matrix.flags.writeable = False
    loader = Loader(ctx)
    shape = {k: loader.value(TOOL[k], table[k], f"cell.tool.{k}") for k in ("radius_mm", "box_mm") if k in table}
    if len(shape) == 2:
        ctx.fail("cell.tool.box_mm", "the tool is a cylinder (radius_mm) or a box (box_mm), not both")
    return Tool(tcp, matrix, mass, cog, _numbered(ctx, table.get("numbered", {})), **shape)


def _numbered(ctx, table) -> dict:
    """[cell.tool] numbered = { <target> = n }: the program selects the controller's numbered tool and
    load n (which must hold the cell's tool) instead of declaring its own."""
    if not isinstance(table, dict):
        ctx.fail("cell.tool.numbered", "expected a table: target = tool number")
    out = {}
    for target in table:
        path = f"cell.tool.numbered.{target}"
        try:
            facts = get_target(target).program.get("tool_data")
        except KeyError:
            ctx.fail(path, "unknown target")
        if not facts:
            ctx.fail(path, f"the {target} controller has no numbered tools here")
        out[target] = ctx.integer(table, target, path, 1, facts["max"])  # the controller's tool number
    return out


def parse_station_config(ctx, raw, path: str, robot: Robot | None, pose_names: list[str]) -> dict:
    """[station.config.<target>]: pose name -> its configuration: target -> {pose: PoseConfig}."""
    if raw is None:
        return {}
    out = {}
    for target, poses in _per_arm(ctx, raw, path, robot).items():
        tpath = f"{path}.{target}"
        if not isinstance(poses, dict):
            ctx.fail(tpath, "expected a table: pose name = configuration")
        out[target] = {}
        for pose, value in poses.items():
            ppath = f"{tpath}.{pose}"
            if pose not in pose_names:
                ctx.fail(ppath, f"no such pose; the station's poses: {', '.join(pose_names)}")
            out[target][pose] = _pose_config(ctx, value, ppath, configuration_of(target), robot.arms[target])
    return out


def parse_cycle_config(ctx, raw, path: str, robot: Robot | None) -> dict:
    """A configuration per target that a whole program cycle is worked in: target -> PoseConfig."""
    if raw is None:
        return {}
    return {
        target: _pose_config(ctx, value, f"{path}.{target}", configuration_of(target), robot.arms[target])
        for target, value in _per_arm(ctx, raw, path, robot).items()
    }


def _per_arm(ctx, raw, path: str, robot: Robot | None) -> dict:
    """A table of targets, each one with an arm in [cell.robot]."""
    if robot is None:
        ctx.fail(path, "a configuration needs [cell.robot]")
    if not isinstance(raw, dict):
        ctx.fail(path, "expected a table of targets")
    for target in raw:
        if target not in robot.arms:
            ctx.fail(f"{path}.{target}", f"no arm for this target in [cell.robot]; allowed: {', '.join(robot.arms)}")
    return raw


def _integers(ctx, value, count: int, low: int, high: int, path: str) -> tuple[int, ...]:
    if not isinstance(value, list) or len(value) != count:
        ctx.fail(path, f"expected {count} integers")
    return tuple(ctx.integer(dict(enumerate(value)), i, f"{path}[{i}]", low, high) for i in range(count))


def _pose_config(ctx, value, path: str, form: str, arm: Arm) -> PoseConfig:
    if isinstance(value, dict) and set(value) == {"joints"}:
        joints = ctx.numbers(value["joints"], 6, f"{path}.joints")
        try:
            check_inside(joints, arm.limits_deg, f"{path}.joints")
        except ArmError as exc:
            ctx.fail(*str(exc).split(": ", 1))
        return PoseConfig("joints", joints)
    if form == "confdata":
        return PoseConfig(form, _integers(ctx, value, 4, -8, 7, path))
    if form == "status_turn":
        if not isinstance(value, dict) or set(value) != {"s", "t"}:
            ctx.fail(path, "expected { s = status, t = turn } or { joints = [...] }")
        return PoseConfig(
            form, (ctx.integer(value, "s", f"{path}.s", 0, 7), ctx.integer(value, "t", f"{path}.t", 0, 63))
        )
    if form == "joints":
        joints = ctx.numbers(value, 6, path)
        try:
            check_inside(joints, arm.limits_deg, path)
        except ArmError as exc:
            ctx.fail(*str(exc).split(": ", 1))
        return PoseConfig("joints", joints)
    ctx.fail(path, "this target has no configuration")
