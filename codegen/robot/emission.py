"""Template variables of the arm: tool, load, home joints and each arm pose's configuration, as literals."""

from __future__ import annotations

import math

from codegen.decimals import format_literal
from codegen.emit import EmitError
from codegen.model.robot import numbered_names
from codegen.poses import FORMAT_DECIMALS, native_values
from codegen.robot.region import station_plan
from codegen.robot.taught import ReachError, configuration

JOINT_DECIMALS = {"deg": 4, "rad": 6}  # 1e-4 deg; 1e-6 rad = 6e-5 deg
MASS_DECIMALS = 3


def _joints(values, unit: str) -> list[str]:
    scale = math.pi / 180.0 if unit == "rad" else 1.0
    return [format_literal(v * scale, JOINT_DECIMALS[unit]) for v in values]


def cell_robot(cell, target) -> dict | None:
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
    return {
        "model": robot.arms[target.name].model,
        "home": _joints(robot.home[target.name], unit),
        "tool": [format_literal(v, d) for v, d in zip(tool, decimals, strict=True)],
        "mass": format_literal(robot.tool.mass_kg, MASS_DECIMALS),
        "cog": [format_literal(v, d) for v, d in zip(cog, decimals[:3], strict=True)],
        "tool_given": robot.tool_given,
        "tool_data": _numbered(target, robot.tool.numbered.get(target.name)),
    }


def _numbered(target, number: int | None) -> dict | None:
    """The controller's numbered tool and load the program selects, or None (it declares its own)."""
    if number is None:
        return None
    tool, load = numbered_names(target.name, number)
    return {"tool": tool, "load": load}


def station_arm(cell, target, station) -> list[dict]:
    """Each arm pose's configuration literal, in the order of the kind's arm_poses; [] without an arm.
    `named`: whether the program names the whole configuration (it holds over the correction region);
    else it names what holds (the status without the turn; the configuration with the check off)."""
    robot = cell.robot
    if robot is None or target.name not in robot.arms:
        return []
    arm = robot.arms[target.name]
    unit = target.program["joint_unit"]
    literal = _LITERALS[target.configuration]
    try:
        taught, named_poses = station_plan(cell, target.name, station)
    except ReachError as exc:  # a taught pose the arm cannot take: no configuration to write
        raise EmitError(str(exc)) from None
    return [
        {
            **literal(configuration(target.configuration, arm, pose.joints), unit),
            "named": named,
            "taught_joints": _joints(pose.joints, unit),  # where the arm stands at the taught pose
        }
        for pose, named in zip(taught, named_poses, strict=True)
    ]


_LITERALS = {  # a target's configuration form -> its template variables
    "confdata": lambda value, unit: {"robconf": ", ".join(str(v) for v in value)},
    "status_turn": lambda value, unit: {"s": str(value[0]), "t": str(value[1])},
    "joints": lambda value, unit: {"joints": _joints(value, unit)},
}


def configuration_literal(target, value) -> dict:
    """A configuration value (codegen/robot/config.py FORMS) as the target's template variables."""
    return _LITERALS[target.configuration](value, target.program["joint_unit"])
