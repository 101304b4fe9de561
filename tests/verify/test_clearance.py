"""verify's clearance check of interpreted traces: hand-written URScript programs run on a UR5e among hand-made
solids, each move swept (joint, linear, a blend's corner), the part counted while the gripper holds it."""

from __future__ import annotations

import numpy as np
import pytest

from codegen.dialects import get_dialect
from codegen.poses import rotvec_from_rotmat
from codegen.robot.arms import catalogue
from codegen.verify.clearance import Gripper, TraceClearance, selected
from codegen.world.engine import Scene
from codegen.world.solids import Box, World, part_box, tool_cylinder, translation

UR5E = catalogue()["UR5e"]
HOME = np.array(UR5E.home_deg)
TOOL = translation(0.0, 0.0, 150.0)
URSCRIPT = get_dialect("urscript")
CLEARANCE = 20.0
GRIP = "standard_digital_out[0]"


def program(*lines: str) -> str:
    return "def prog():\n  set_tcp(p[0, 0, 0.15, 0, 0, 0])\n" + "".join(f"  {line}\n" for line in lines) + "end\n"


def trace_of(text: str, start=HOME):
    return URSCRIPT.load(text, "prog.script").run({}, arm=UR5E, start_joints=list(start))


def checker(solids: dict, part: Box | None = None) -> TraceClearance:
    tool = tool_cylinder(TOOL, 25.0)
    free = Scene(UR5E, World(solids), tool=tool)
    held = free if part is None else Scene(UR5E, World(solids), tool=tool, part=part)
    return TraceClearance({False: free, True: held}, CLEARANCE, URSCRIPT, "prog.script", Gripper(GRIP, True))


def joints_text(q) -> str:
    return "[" + ", ".join(f"{v:.6f}" for v in np.radians(q)) + "]"


def plate_at_home_tip() -> Box:
    """A 60 mm plate across the tool's path where the tool stands at home (axis 1 turning)."""
    tip = (UR5E.kin.fk(HOME) @ TOOL)[:3, 3]
    along = np.cross([0.0, 0.0, 1.0], tip)
    along /= np.linalg.norm(along)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 2] = along, (0.0, 0.0, 1.0)
    pose[:3, 1] = np.cross(pose[:3, 2], along)
    pose[:3, 3] = tip - (0.0, 0.0, 30.0)
    return Box((60.0, 60.0, 80.0), pose)


def swing(to_deg: float) -> str:
    start, end = HOME.copy(), HOME.copy()
    start[0], end[0] = -60.0, to_deg
    return program(f"movej({joints_text(start)})", f"movej({joints_text(end)})")


def test_a_swing_through_a_solid_is_named_by_its_move_body_and_solid():
    check = checker({"plate": plate_at_home_tip()})
    away = HOME.copy()
    away[0] = -60.0
    least, breach = check.check(trace_of(swing(60.0), away), away)
    assert breach is not None and breach.where == "prog.script:4"  # the second movej, through home
    assert (breach.what, breach.body, breach.other) == ("joint move", "tool", "plate")
    assert breach.distance < 0
    assert least == breach
    text = breach.text(CLEARANCE)
    assert text.startswith("prog.script:4: the joint move: the tool cuts") and "into plate" in text


def test_the_same_program_short_of_the_solid_is_clear():
    check = checker({"plate": plate_at_home_tip()})
    away = HOME.copy()
    away[0] = -60.0
    least, breach = check.check(trace_of(swing(-20.0), away), away)
    assert breach is None and least.distance >= CLEARANCE


def corner_program(blend_m: float) -> str:
    """Down-pointing tool: a line along -y, a corner at (400, -100, 300) mm, a line along -x."""
    return program(
        "movej(p[0.4, 0.2, 0.3, 3.14159265, 0, 0])",
        f"movel(p[0.4, -0.1, 0.3, 3.14159265, 0, 0], r={blend_m})",
        "movel(p[0.2, -0.1, 0.3, 3.14159265, 0, 0])",
    )


def corner_post() -> Box:
    """A post inside the corner, 30 mm from either line's tool (radius 25), within the tool's height."""
    return Box((20.0, 20.0, 140.0), translation(335.0, -35.0, 350.0))


@pytest.mark.parametrize(("blend_m", "cuts"), [(0.0, False), (0.02, False), (0.15, True)])
def test_a_blend_wide_enough_cuts_its_corner_into_a_solid(blend_m, cuts):
    check = checker({"post": corner_post()})
    trace = trace_of(corner_program(blend_m))
    _, breach = check.check(trace, HOME)
    if not cuts:
        assert breach is None, breach
        return
    assert breach is not None and breach.where == "prog.script:4"
    assert breach.what == "blend's corner (150 mm zone)" and breach.other == "post"


def test_the_part_counts_only_while_the_gripper_holds_it():
    """Over a low block: the tool alone clears it by 40 mm, the part hanging 60 mm below the TCP does not."""
    block = Box((100.0, 100.0, 100.0), translation(400.0, 0.0, 210.0))  # its top at 260 mm
    part = part_box((50.0, 50.0, 60.0), TOOL)
    check = checker({"block": block}, part)
    over = ["movej(p[0.4, 0.2, 0.3, 3.14159265, 0, 0])", "movel(p[0.4, -0.2, 0.3, 3.14159265, 0, 0])"]
    _, breach = check.check(trace_of(program(*over)), HOME)
    assert breach is None  # no part: 40 mm
    held = program("set_standard_digital_out(0, True)", *over)
    _, breach = check.check(trace_of(held), HOME)
    assert breach is not None and (breach.body, breach.other) == ("part", "block")
    released = program(over[0], "set_standard_digital_out(0, True)", "set_standard_digital_out(0, False)", over[1])
    _, breach = check.check(trace_of(released), HOME)
    assert breach is None
    _, breach = check.check(trace_of(program(*over)), HOME, held=True)  # a part held at the start
    assert breach is not None and breach.body == "part"


def test_each_distinct_move_is_swept_once():
    check = checker({"plate": plate_at_home_tip()})
    away = HOME.copy()
    away[0] = -60.0
    trace = trace_of(swing(-20.0), away)
    check.check(trace, away)
    swept = check.swept
    check.check(trace, away)
    assert swept == 2 and check.swept == swept


def test_a_move_to_the_same_joints_from_elsewhere_is_swept_again():
    """The memo's key is the whole move: the same end reached through the plate is not taken for the clear one."""
    check = checker({"plate": plate_at_home_tip()})
    away, other = HOME.copy(), HOME.copy()
    away[0], other[0] = -60.0, 60.0
    _, breach = check.check(trace_of(swing(-20.0), away), away)
    assert breach is None
    through = program(f"movej({joints_text(other)})", f"movej({joints_text(np.add(HOME, [-20.0, 0, 0, 0, 0, 0]))})")
    _, breach = check.check(trace_of(through, other), other)
    assert breach is not None and breach.where == "prog.script:4"


def test_the_cases_swept_every_scenario_and_a_spread_of_each_category():
    categories = ["start_away"] + ["corner"] * 16 + ["random"] * 1000 + ["vision_never"] * 3
    scenarios = ["start_away"] + ["corner"] * 16 + ["random"] * 1000 + ["device_silent"] * 3
    chosen = selected(categories, scenarios)
    assert chosen[0] and all(chosen[-3:])  # the common scenarios, every one
    corners = [i for i in range(1, 17) if chosen[i]]
    randoms = [i - 17 for i in range(17, 1017) if chosen[i]]
    assert corners == [1, 3, 5, 7, 9, 11, 13, 15]  # eight, one in two
    assert randoms == [0, 125, 250, 375, 500, 625, 750, 875]  # eight, spread over all of them


def tcp_text(dz_mm: float) -> str:
    """The TCP at home moved dz_mm along the base's z, as a URScript pose (m, rotation vector)."""
    pose = UR5E.kin.fk(HOME) @ TOOL
    x, y, z = (pose[:3, 3] + (0.0, 0.0, dz_mm)) / 1000.0
    rx, ry, rz = rotvec_from_rotmat(pose[:3, :3])
    return f"p[{x:.6f}, {y:.6f}, {z:.6f}, {rx:.8f}, {ry:.8f}, {rz:.8f}]"


def test_where_the_gripper_acts_the_tool_may_touch_what_it_takes_from():
    """Straight down 100 mm from home onto a table (the tool's end 5 mm over it), the gripper closes, straight up:
    the table is not measured against the tool along those straight moves; the same descent without the gripper
    acting is a breach, and so is a joint move onto the table."""
    tip = (UR5E.kin.fk(HOME) @ TOOL)[:3, 3]
    table = Box((80.0, 80.0, 20.0), translation(tip[0], tip[1], tip[2] - 100.0 - 5.0 - 10.0))  # top 5 mm under
    check = checker({"table": table})
    down, up = f"movel({tcp_text(-100.0)})", f"movel({tcp_text(0.0)})"
    least, breach = check.check(trace_of(program(down, "set_standard_digital_out(0, True)", up)), HOME)
    assert breach is None and least.other != "table"
    _, breach = check.check(trace_of(program(down, up)), HOME)
    assert breach is not None and (breach.where, breach.other) == ("prog.script:3", "table")
    dip = program(down.replace("movel", "movej"), "set_standard_digital_out(0, True)", up)
    _, breach = check.check(trace_of(dip), HOME)
    assert breach is not None and breach.other == "table" and breach.what == "joint move"
