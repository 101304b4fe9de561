"""verify sweeps a circular move (URScript movec, KRL CIRC, RAPID MoveC) along its arc: a solid beside the arc's
bulge, far from the straight way between its ends, fails the move; the same solid moved off the arc does not."""

from __future__ import annotations

import numpy as np
import pytest

from codegen.dialects import get_dialect
from codegen.robot.arms import catalogue
from codegen.verify.clearance import TraceClearance
from codegen.world.engine import Scene
from codegen.world.solids import Box, World, tool_cylinder, translation

UR5E = catalogue()["UR5e"]
HOME = np.array(UR5E.home_deg)
TOOL = translation(0.0, 0.0, 150.0)
URSCRIPT = get_dialect("urscript")
CLEARANCE = 20.0
DOWN = "3.14159265, 0, 0"  # the tool pointing down


def check_among(solids: dict) -> TraceClearance:
    free = Scene(UR5E, World(solids), tool=tool_cylinder(TOOL, 25.0))
    return TraceClearance({False: free, True: free}, CLEARANCE, URSCRIPT, "prog.script")


def arc_trace(mode: int = 0):
    """From (400, -150, 300) mm through (550, 0, 300) to (400, 150, 300): the arc's circle has its centre at (~362, 0)
    and bulges out to x = 550 mm, where the arm's way between the ends (joints turning about axis 1) stays within
    about 430 mm of the base's axis."""
    text = (
        "def prog():\n  set_tcp(p[0, 0, 0.15, 0, 0, 0])\n"
        f"  movej(get_inverse_kin(p[0.4, -0.15, 0.3, {DOWN}], qnear=get_actual_joint_positions()))\n"
        f"  movec(p[0.55, 0, 0.3, {DOWN}], p[0.4, 0.15, 0.3, {DOWN}], a=1.2, v=0.25, r=0, mode={mode})\n"
        "end\n"
    )
    return URSCRIPT.load(text, "prog.script").run({}, arm=UR5E, start_joints=list(HOME))


def post(x_mm: float) -> Box:
    """A post 20 mm square standing at (x, 0) over the tool's height."""
    return Box((20.0, 20.0, 200.0), translation(x_mm, 0.0, 320.0))


@pytest.mark.parametrize("mode", [0, 1])
def test_a_post_at_the_arcs_bulge_fails_the_circular_move(mode):
    trace = arc_trace(mode)
    assert trace.moves[-1].arc is not None  # the run keeps the arc it followed
    tcp = [UR5E.kin.fk(np.asarray(m.joints)) @ TOOL for m in trace.moves[-2:]]
    assert all(abs(p[0, 3] - 400.0) < 1e-3 for p in tcp)  # both ends at x = 400: the post is 150 mm beyond them
    _, breach = check_among({"post": post(550.0)}).check(trace, HOME)
    assert breach is not None and breach.where == "prog.script:4", breach
    assert (breach.what, breach.body, breach.other) == ("circular move", "tool", "post") and breach.distance < 0


def test_the_post_beyond_the_arc_is_clear():
    least, breach = check_among({"post": post(620.0)}).check(arc_trace(), HOME)
    assert breach is None and least.distance >= CLEARANCE
