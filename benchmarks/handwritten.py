"""Issue 16's yardstick: a verified case of the demo cell written by hand in Python, without the interpreter.

What a case costs when the program is not interpreted. Per case, as `codegen verify` does:
  - the reference: verify's accepted traces and the physical check (codegen/kinds/station/cases.py), unchanged;
  - the program written by hand for a point station (source 000), in float32 scalars as a controller
    computes: the reading's guards (range, shift squared, rotation), the correction D from the reading
    and the station's mark, and every taught pose moved by D except the station's `fixed` poses, which the
    program keeps as taught (on the arm's own carrier); a halt where the guards say so;
  - the arm, where the cell has one: from the home joints, each moved pose solved for the arm (the
    analytic solutions) and its joints chosen by the controller's rule as the program names the move (a
    joint move by its configuration, or the solution nearest where the arm stands; a linear move keeps the
    configuration), written here after codegen/dialects/core/arm.py's rules;
  - the comparison: each move's position and orientation against the reference within the float32
    tolerances, and the joints against verify's reference rule (codegen/kinds/station/region.py move_joints)
    applied to the same solutions, as verify's arm check does: two statements of the controllers' rules.
Not included, because a hand-written case has nothing to interpret there: the vision handshake (its
polling), the gripper's signals and feedback, the move settings and the log line's text. The interpreter
does all of these in every case; the ratio interpreter / hand-written is therefore the interpreter's whole
overhead, the handshake's simulation included.
"""

from __future__ import annotations

import math

import numpy as np

from codegen.controllers import get_target
from codegen.guard import INVALID_READING, ROTATION_OVER_LIMIT, SHIFT_OVER_LIMIT, reading_in_range
from codegen.kinds.station.cases import Case, _truth_problem, accepted_traces
from codegen.kinds.station.joints import expected_joints
from codegen.kinds.station.plan import taught_poses
from codegen.kinds.station.section import section_of
from codegen.reference import home_move
from codegen.robot import solve
from codegen.robot.config import FORMS, with_status
from codegen.robot.expect import JOINT_TOLERANCE_DEG
from codegen.verify.checks import TOLERANCES, pose_errors

F = np.float32


def _wrap(angle: np.float32) -> np.float32:
    while angle > 180:
        angle -= F(360)
    while angle <= -180:
        angle += F(360)
    return angle


def program(cell, reading) -> tuple[str, list[np.ndarray]]:
    """The station's program by hand in float32: ("ok", moved poses) or ("halt", reason), no moves."""
    section = section_of(cell)
    station = section.station_by_id(reading.station_id)
    x, y, theta = F(reading.x), F(reading.y), F(reading.theta)
    if not reading_in_range(float(x), float(y), float(theta)):
        return INVALID_READING, []
    tx, ty, t_theta = (F(v) for v in station.spec.mark)
    dx, dy = x - tx, y - ty
    if dx * dx + dy * dy > F(section.limits.max_shift_mm) ** 2:
        return SHIFT_OVER_LIMIT, []
    rotation = _wrap(theta - t_theta)
    if abs(rotation) > F(section.limits.max_rotation_deg):
        return ROTATION_OVER_LIMIT, []
    phi = F(section.angle_sign) * rotation * F(math.pi / 180.0)
    c, s = F(math.cos(phi)), F(math.sin(phi))
    ox, oy = x - (c * tx - s * ty), y - (s * tx + c * ty)  # D = T(x, y) Rz(phi) T(-tx, -ty)
    moved = []
    for pose in station.path:
        m = pose.matrix().astype(F)
        if pose.name in station.spec.fixed:  # on the arm's own carrier: the program keeps it as taught
            moved.append(m.astype(np.float64))
            continue
        out = np.empty((4, 4))
        for col in range(3):
            a, b, z = m[0, col], m[1, col], m[2, col]
            out[0, col], out[1, col], out[2, col] = c * a - s * b, s * a + c * b, z
        out[0, 3], out[1, 3] = c * m[0, 3] - s * m[1, 3] + ox, s * m[0, 3] + c * m[1, 3] + oy  # float32 sums
        out[2, 3] = m[2, 3]
        out[3] = (0.0, 0.0, 0.0, 1.0)
        moved.append(out)
    return "ok", moved


def case(cell, target: str, one: Case) -> str | None:
    """One verified case: None when the hand-written program agrees with the reference, else the problem."""
    accepted, _ = accepted_traces(cell, one)
    expected = accepted[0]
    untrue = _truth_problem(cell, one, expected)
    if expected.status != "ok":
        if expected.reason in (INVALID_READING, SHIFT_OVER_LIMIT, ROTATION_OVER_LIMIT):
            status, _ = program(cell, one.reading)
            return None if status == expected.reason else f"halt {status}, expected {expected.reason}"
        return untrue  # a halt before the station's math (no answer, unknown id, gripper): nothing to compute
    status, poses = program(cell, one.reading)
    if status != "ok":
        return f"halt {status}, expected the moves"
    pos_tol, rot_tol = TOLERANCES["float32"]
    for got, want in zip(poses, expected.moves, strict=True):
        position, orientation = pose_errors(got.tolist(), want.tcp2base.tolist())
        if not (position <= pos_tol and orientation <= rot_tol):
            return f"{want.pose_name}: {position:.6f} mm, {orientation:.6f} deg"
    home = home_move(cell, target)
    if home is None:
        return untrue
    arm, tool = cell.robot.arms[target], cell.robot.tool
    form = get_target(target).configuration
    taught, named = taught_poses(cell, target, expected.station)
    by_name: dict = {}
    for pose, full in zip(taught, named, strict=True):
        by_name.setdefault(pose.name, (pose, full))
    solutions = [solve.branches(arm, solve.flange_poses(p, tool.tcp2flange)) for p in poses]
    previous, branch, joints = home[1], None, []
    for move, sols in zip(expected.moves, solutions, strict=True):
        pose, full = by_name[move.pose_name]
        q, chosen = _rule(arm, form, pose, full, sols, previous)
        if np.isnan(q).any() or (pose.motion == "linear" and branch is not None and int(chosen) != branch):
            return f"{move.pose_name}: no joints by the controller's rule"
        joints.append(q)
        previous, branch = q, int(chosen)
    want = expected_joints(cell, target, expected.station, expected.moves, home[1], solutions)
    for move, q, w in zip(expected.moves, joints, want, strict=True):
        if not float(np.max(np.abs(q - w))) <= JOINT_TOLERANCE_DEG:
            return f"{move.pose_name}: joints {q} against {w}"
    return untrue


def _rule(arm, form: str, pose, full: bool, sols: np.ndarray, previous: np.ndarray):
    """The joints a move of the program takes: a joint move to its named configuration (UR: the solution
    nearest the taught joints, get_inverse_kin's qnear), or with only KUKA's Status bits named the nearest
    of that status, or else the nearest solution; a linear move the nearest (its configuration is checked
    by the caller)."""
    if pose.motion != "joint":
        return solve.nearest(arm, sols, previous)
    if form == "joints":
        return solve.nearest(arm, sols, pose.joints)
    value = FORMS[form].of(arm, pose.joints)
    if full:
        return FORMS[form].select(arm, sols, value)
    if form == "status_turn":
        return solve.nearest(arm, with_status(arm, sols, value[0]), previous)
    return solve.nearest(arm, sols, previous)
