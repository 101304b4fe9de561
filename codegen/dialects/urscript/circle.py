"""URScript movec: the circular move through a via point, with the orientation its mode gives along the arc."""

# URScript Script Directory (e-Series) 14.21, movec(pose_via, pose_to, a=1.2, v=0.25, r=0, mode=0) (STATED):
# "TCP moves on the circular arc segment from current pose, through pose_via to pose_to. Accelerates to and moves
# with constant tool speed v."
# - pose_via: "path point (note: only position is used)"; pose_to: "target pose (note: only position is used
#   in Fixed orientation mode)"; a: tool acceleration (m/s^2), v: tool speed (m/s), r: blend radius (m).
# - mode 0, Unconstrained: "Interpolate orientation from current pose to target pose (pose_to)".
# - mode 1, Fixed: "Keep orientation constant relative to the tangent of the circular arc (starting from
#   current pose)": the tool turns with the arc, about its axis, by the arc's angle (so a TCP that must keep
#   one orientation in space moves with mode 0 and pose_to in that orientation).
# - pose_via and pose_to may be joint positions (forward kinematics): not modelled here (refused).
# Modelled: the move's time is the arc's length over v (acceleration not modelled, as for movel); the TCP
# runs along the arc at that speed (codegen/dialects/core/watch.py records it for the threads that watch
# it); mode 0's orientation is the rotation from the start's to pose_to's, scaled by the share of the arc.
# Assumed: start, via and end on one line (a full circle in one movec among them: end = start) are refused,
# as the arc is then not defined (the manual does not say what the controller does); a movec while a conveyor
# is tracked is not modelled (refused).

from __future__ import annotations

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.machine import MoveEvent
from codegen.dialects.core.values import RunError, show
from codegen.dialects.core.watch import Path
from codegen.poses import rotmat_from_rotvec, rotvec_from_rotmat

PARAMS = ("pose_via", "pose_to", "a", "v", "r", "mode")
DEFAULTS = {"a": 1.2, "v": 0.25, "r": 0.0, "mode": 0}
MM_PER_M = 1000.0


class Arc(Path):
    """The circle through start, via and end (Path: positions, its length) with movec's orientation."""

    def __init__(self, start: np.ndarray, end: np.ndarray, via: np.ndarray, mode: int) -> None:
        super().__init__(start, end, via)
        self.mode = mode
        _centre, _radius, u, v = self.circle
        self.normal = np.cross(u, v)  # the arc turns about it (right-handed, towards the via point)
        r0 = start[:3, :3]
        if mode == 1:
            self.turn = self.normal * self.sweep  # about the arc's axis, with the tangent
        else:
            self.turn = r0 @ rotvec_from_rotmat(r0.T @ end[:3, :3])  # base frame: start's to pose_to's

    def rotation(self, s: float) -> np.ndarray:
        if not self.turn.any():  # the orientation held (pose_to's is the start's): nothing to turn
            return self.start[:3, :3]
        return rotmat_from_rotvec(self.turn * s) @ self.start[:3, :3]

    def end_pose(self) -> np.ndarray:
        out = self.end.copy()
        out[:3, :3] = self.rotation(1.0)
        return out

    def pose(self, s: float) -> np.ndarray:
        out = super().pose(s)
        out[:3, :3] = self.rotation(s)
        return out


def _arguments(args, kwargs, where: str) -> dict:
    if len(args) > len(PARAMS):
        raise RunError(f"{where}: movec takes at most {len(PARAMS)} arguments ({', '.join(PARAMS)}), got {len(args)}")
    unknown = sorted(set(kwargs) - set(PARAMS))
    if unknown:
        raise RunError(f"{where}: movec has no parameter {unknown[0]} (it takes {', '.join(PARAMS)})")
    bound = dict(zip(PARAMS, args, strict=False))
    twice = sorted(set(bound) & set(kwargs))
    if twice:
        raise RunError(f"{where}: movec: {twice[0]} given twice")
    bound.update(kwargs)
    for name in ("pose_via", "pose_to"):
        if name not in bound:
            raise RunError(f"{where}: movec needs {name}")
    return {**DEFAULTS, **bound}


def builtin(pose_of, number_of, in_thread):
    """movec for the interpreter; pose_of, number_of: the dialect's argument checks; in_thread(fr): the
    thread running now, None in the main program."""

    def movec(fr, args, kwargs, where):
        if in_thread(fr) is not None:
            raise RunError(f"{where}: movec from a thread: not modelled here (the main program moves the arm)")
        bound = _arguments(args, kwargs, where)
        points = {}
        for name in ("pose_via", "pose_to"):
            value = bound[name]
            if isinstance(value, list):
                raise RunError(f"{where}: movec {name} as joint positions: not modelled here (give a pose p[...])")
            pose = pose_of(value, where)
            posemath.check_finite(pose.values(), where, f"movec {name}")
            points[name] = posemath.matrix_from_ur(pose.values())
        settings = {k: float(number_of(bound[k], where, f"movec {k}")) for k in ("a", "v", "r")}
        mode = bound["mode"]
        if isinstance(mode, bool) or mode not in (0, 1):
            raise RunError(f"{where}: movec mode must be 0 (unconstrained) or 1 (fixed), got {show(mode)}")
        if not settings["v"] > 0 or not settings["a"] > 0 or not settings["r"] >= 0:
            raise RunError(f"{where}: movec needs a > 0, v > 0 and r >= 0")
        if fr.m.tracking is not None:
            raise RunError(f"{where}: movec while tracking a conveyor: not modelled here")
        settings["mode"] = int(mode)
        settings["load"] = fr.m.state.payload
        machine = fr.m
        start = machine._last_tcp2base
        if start is None and machine.last_move is not None:  # after a move to joints: its pose, where known
            machine.arm.resolve()
            start = machine._last_tcp2base = machine.last_move.tcp2base
        via, end = points["pose_via"], points["pose_to"]
        arc = None
        if start is not None:
            try:
                arc = Arc(start, end, via, int(mode))
            except RunError as exc:
                raise RunError(f"{where}: movec: {exc}") from None
            end = arc.end_pose()
        event = MoveEvent("circular", end, int(where.split(":")[1]), settings)
        machine.arm.from_start()  # where the arm stands, when the run knows it
        machine.arm.to_pose(event, where, "keep")  # the configuration of the start, as movel
        speed = settings["v"] * MM_PER_M
        if arc is None:  # from a pose the run does not know: its time, not its path
            machine.move(event, speed, via=via)
            return
        # the move with its own path (the orientation along the arc); movec returns when the arm has arrived
        machine.move(event, speed, via=via, path=arc)

    return movec
