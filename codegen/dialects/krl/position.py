"""Where a KRL motion is: the active $BASE in the robot's base frame ($ROBROOT), the base of the move under way."""

from __future__ import annotations

import numpy as np

from codegen.dialects.core.machine import MoveEvent
from codegen.dialects.core.values import Record
from codegen.dialects.krl.builtins import cart_matrix, frame, xyzabc
from codegen.poses import invert

# $BASE keeps its value from program to program (KSS 8 system variables): a program starts in whatever
# base was active. The interpreter assumes one that is not the robot's base, so a program that moves
# without setting $BASE ($NULLFRAME, or a BASE_DATA) moves somewhere else in its trace.
ACTIVE_BASE_AT_START = (250.0, -120.0, 40.0, 30.0, 0.0, 0.0)


def world2robot(root: Record):
    """The world in the robot's base frame: the inverse of $ROBROOT as a 4x4 matrix."""
    return invert(cart_matrix(root))


def base2robot(sysvars: dict) -> np.ndarray:
    """The active $BASE in the robot's base frame (4x4 mm): $BASE is in the world, the trace in the robot's
    base frame ($ROBROOT); a program that never set $BASE moves in the one active when it started."""
    given, root = sysvars.get("$BASE"), sysvars.get("$ROBROOT")
    last = _LAST_BASE
    if given is last[0] and root is last[1] and given is not None:  # records never change in place
        return last[2]
    base = given or frame(ACTIVE_BASE_AT_START)
    out = cart_matrix(base) if xyzabc(base) != (0, 0, 0, 0, 0, 0) else np.eye(4)  # $NULLFRAME: identity
    if "$ROBROOT" in sysvars:
        out = world2robot(root) @ out
    out.flags.writeable = False  # shared by the moves planned in this base
    _remember_base(given, root, out)
    return out


# ($BASE, $ROBROOT, base2robot) of the last motion: each move asks again, mostly in the same base; the records are
# held, so that their identities stay theirs
_LAST_BASE: tuple = (object(), object(), None)


def _remember_base(given, root, out: np.ndarray) -> None:
    global _LAST_BASE
    _LAST_BASE = (given, root, out)


def record_base(machine, event: MoveEvent, base: np.ndarray) -> None:
    """Keep the $BASE a move was planned in: $POS_INT is in the base of the motion under way."""
    machine.state.move_bases[id(event)] = base


def motion_base(machine, t: float) -> np.ndarray:
    """The $BASE (robot's base frame) of the move under way at time t, or of the last one that ended by
    then; the program's $BASE before any move."""
    bases = machine.state.move_bases
    watching = machine.watching
    for seg in reversed(watching.segments if watching is not None else []):
        if seg.t0 <= t and id(seg.end) in bases:
            return bases[id(seg.end)]
    return base2robot(machine.state.sysvars)
