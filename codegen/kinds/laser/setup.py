"""The laser calibration's start for one case: the controller's presets, the tool, the arm's start joints."""

from dataclasses import dataclass

import numpy as np

from codegen.controllers import get_target
from codegen.kinds.laser import confirm
from codegen.kinds.laser import program as lp
from codegen.kinds.laser.kind import KIND
from codegen.kinds.laser.section import laser_of
from codegen.kinds.laser.verify import (
    STEP_LIMIT,
    LaserCase,
    previous_tcp,
    station_for,
)
from codegen.poses import native_values
from codegen.robot import solve
from codegen.verify.plan import START_AWAY_DEG, Setup, tool_inputs


def _tooldata(cell, tcp) -> list:
    """A RAPID tooldata with the TCP at tcp (mm), the cell's orientation and load."""
    tool = cell.robot.tool
    quaternion = native_values(tool.tcp, cell.pose_format, "abb")[3:]
    return [True, [list(map(float, tcp)), list(quaternion)], [tool.mass_kg, list(tool.cog_mm), [1, 0, 0, 0], 0, 0, 0]]


def _xyzabc(cell, tcp) -> tuple:
    abc = native_values(cell.robot.tool.tcp, cell.pose_format, "xyzabc")[3:]
    return (*map(float, tcp), *abc)


def _pose_m(cell, tcp) -> tuple:
    """An installation variable holding a pose: the TCP at tcp (mm) in m, the cell's orientation (rotation vector)."""
    rotation = native_values(cell.robot.tool.tcp, cell.pose_format, "ur")[3:]
    return (*(float(v) / 1000.0 for v in tcp), *map(float, rotation))


# How verify gives a target's production tool its value before the run (the last calibration's), by the form of
# the target's data ([program.laser] production_tool preset): a numbered tool as X, Y, Z, A, B, C; a tooldata
# record; an installation variable (a pose), given as the input the target's production_tool names (input: the
# program's name of it where none is given); none: nothing, what it holds is judged as it was where the program
# does not write it
PRESETS = {
    "TOOL_DATA": _xyzabc,
    "tooldata": _tooldata,
    "installation": _pose_m,
    "none": None,
}


def _preset(cell, target, tcp, case: LaserCase) -> dict:
    spec = KIND.facts(target)["production_tool"]
    make = PRESETS[spec["preset"]]
    if make is None or case.without_production_tool:
        return {}
    name = lp.production_name(cell, target)
    return {spec.get("input", "{name}").format(name=name): make(cell, tcp)}


@dataclass
class LaserSetup(Setup):
    """Setup with the run's clock limit: a case that waits for good (nobody answers) ends there."""

    max_seconds: float | None = None

    def run_options(self, arm, step_limit: int | None) -> dict:
        options = super().run_options(arm, step_limit)
        if self.max_seconds is not None:
            options["max_seconds"] = self.max_seconds
        return options


def _saved(cell, target) -> tuple[str, ...]:
    """The production tool as its module's saved file keeps it, where the target's program saves one."""
    name = lp.saved_name(cell, target)
    return () if name is None else (name,)


def setup(cell, target_name: str, case: LaserCase) -> Setup:
    target = get_target(target_name)
    silent = confirm.unanswered(target, case)
    error = lp.production_name(cell, target) if case.without_production_tool else None
    return LaserSetup(
        # the controller's numbered tool and load where the cell names one ([cell.tool] numbered), the production
        # tool as the last calibration left it over it (a numbered production tool is that tool)
        {**tool_inputs(cell, target_name), **_preset(cell, target, previous_tcp(cell, case), case)},
        (station_for(cell, target, case), *confirm.devices(target, case)),
        {},
        start_joints(cell, target_name, case),
        (*lp.kept_names(target).values(), lp.production_name(cell, target), *_saved(cell, target)),
        STEP_LIMIT,
        float(target.program["signal_cycle_s"]),
        confirm.NO_ANSWER if silent else error,
        confirm.WAIT_S if silent else None,
    )


def production_cases(cell, target_name: str) -> list[LaserCase]:
    """Where the production tool is an installation variable: an installation without it (the program must stop
    with the controller's error naming it before it moves, not write the TCP into a variable of its own)."""
    if KIND.facts(get_target(target_name))["production_tool"]["preset"] != "installation":
        return []
    return [
        LaserCase(
            "installation_without_tool", cell.robot.tool.tcp2flange.copy(), noise=0.0, without_production_tool=True
        )
    ]


def pose_in_s(cell, point, rotation=None) -> np.ndarray:
    """The TCP at point (S, mm) in the base frame, in the calibration's orientation (or rotation, base frame)."""
    laser = laser_of(cell)
    sensor2base = laser.sensor_frame.matrix()
    out = np.eye(4)
    out[:3, :3] = sensor2base[:3, :3] @ lp.DOWN @ cell.robot.tool.tcp2flange[:3, :3] if rotation is None else rotation
    out[:3, 3] = sensor2base[:3, :3] @ np.asarray(point, dtype=float) + sensor2base[:3, 3]
    return out


# A start this far either side of the station's column's boundary (mm): beyond float32 and the arm's standing error,
# within the column's margin for a stop (offset_max_mm): a column drawn wider or narrower by that much shows
EDGE_MM = 1.0


def _column_point(laser, where: str) -> tuple[float, float, float]:
    """A start by the station's column (S, mm): beside it (at 45 deg, half way up), above, below, or just inside."""
    column = lp.zone(laser)
    half = (column["low"] + column["high"]) / 2.0
    side = {"out": column["r"] + EDGE_MM, "in": column["r"] - EDGE_MM}
    h = laser.circle_mm / 2.0**0.5
    return {
        "column_side_out": (side["out"] / 2.0**0.5, side["out"] / 2.0**0.5, half),
        "column_side_in": (side["in"] / 2.0**0.5, side["in"] / 2.0**0.5, half),
        "column_top_out": (h, h, column["high"] + EDGE_MM),
        "column_bottom_out": (0.0, 0.0, column["low"] - EDGE_MM),
    }[where]


# the starts where the program must stop before the arm moves (away from home and outside the station's column)
STOPPING_STARTS = ("away", "column_side_out", "column_top_out", "column_bottom_out")


def start_joints(cell, target_name: str, case: LaserCase):
    robot = cell.robot
    if robot is None or target_name not in robot.arms:
        return None
    home = np.asarray(robot.home[target_name], dtype=float)
    if case.start == "away":
        return home + np.array(START_AWAY_DEG)
    if case.start != "home":  # a stopped calibration's place (the first circle's start), or by the column
        laser = laser_of(cell)
        point = lp.circle_points(laser, 0)["start"] if case.start == "mid_cycle" else _column_point(laser, case.start)
        tcp2base = pose_in_s(cell, point)
        arm = robot.arms[target_name]
        joints, _ = solve.nearest(arm, solve.branches(arm, solve.flange_poses(tcp2base, robot.tool.tcp2flange)), home)
        return joints
    return home
