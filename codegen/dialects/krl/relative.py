"""KRL relative motions: PTP_REL / SPTP_REL by axis values, LIN_REL / SLIN_REL / PTP_REL by a shift (KSS 8)."""

from __future__ import annotations

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.values import Record, RunError, f32
from codegen.dialects.krl.builtins import XYZABC, valid
from codegen.dialects.krl.position import base2robot
from codegen.dialects.krl.sysvars import axis_act
from codegen.poses import invert

# KSS 8 programming manual for system integrators, PTP_REL / LIN_REL (and SPTP_REL / SLIN_REL of KSS 8.3): the
# target is given relative to where the previous motion ends: an axis aggregate {A1 10} adds to the axes (PTP), a
# cartesian aggregate {Z 300} shifts the TCP along the axes of the active $BASE, or with #TOOL after the motion
# along the tool's own axes. What the interpreter models: axis offsets, and shifts (X, Y, Z) with the orientation
# kept; a relative rotation (A, B, C not 0) is refused: how the controller composes the angles is not confirmed
# here. The motion keeps the arm's configuration (a cartesian target without Status and Turn).
REFERENCES = frozenset({"#BASE", "#TOOL"})


def relative_target(value, reference: str, where: str):
    """fr -> the absolute target of a relative motion: an E6AXIS, or a FRAME in the active $BASE."""
    if reference not in REFERENCES:
        raise RunError(f"{where}: a relative motion is #BASE or #TOOL, not {reference}")

    def absolute(fr):
        offset = valid(value(fr), where, "relative target")
        if not isinstance(offset, Record) or offset.type not in (None, "FRAME", "POS", "E6POS", "AXIS", "E6AXIS"):
            raise RunError(f"{where}: a relative motion takes an aggregate ({{Z 300}} or {{A1 10}})")
        axes = [k for k in offset if k.startswith("A") and k[1:].isdigit()]
        if axes or offset.type in ("AXIS", "E6AXIS"):
            return _axes(fr, offset, where)
        return _shift(fr, offset, reference, where)

    return absolute


def _axes(fr, offset: Record, where: str) -> Record:
    now = axis_act(fr, where)
    out = now.shallow()
    for i in range(1, 7):
        delta = offset.get(f"A{i}")
        if delta is not None:
            out[f"A{i}"] = f32(float(now[f"A{i}"]) + float(valid(delta, where, f"A{i}")))
    return out


def _shift(fr, offset: Record, reference: str, where: str) -> Record:
    if any(float(valid(offset.get(k, 0.0), where, k)) != 0.0 for k in ("A", "B", "C")):
        raise RunError(f"{where}: a relative rotation (A, B, C) is not modelled by this interpreter (a shift is)")
    last = fr.m.last_move
    if last is not None and last.tcp2base is None:
        fr.m.arm.resolve()  # a PTP to axis values: its pose from the arm's kinematics
    if last is None or last.tcp2base is None:
        raise RunError(f"{where}: a relative motion: where the previous motion ends is not known here")
    shift = np.array([float(valid(offset.get(k, 0.0), where, k)) for k in ("X", "Y", "Z")])
    base = base2robot(fr.m.state.sysvars)
    pose = last.tcp2base.copy()
    axes = pose[:3, :3] if reference == "#TOOL" else base[:3, :3]
    pose[:3, 3] = pose[:3, 3] + axes @ shift
    values = posemath.xyzabc_from_matrix(invert(base) @ pose)
    return Record("FRAME", {k: f32(v) for (k, _), v in zip(XYZABC, values, strict=True)})
