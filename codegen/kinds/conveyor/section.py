"""The [conveyor] table of a cell file: the belt's encoder scale, its frame and the camera's offset."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from codegen.kinds.conveyor.keys import CONVEYOR
from codegen.kinds.conveyor.pick import parse_pick
from codegen.model.loader import Loader, build

UNIT_TOL = 1e-6


@dataclass(frozen=True)
class Conveyor:
    """counts_per_mm: signed (negative: the counter runs down as the belt travels); origin: the belt
    frame's origin (the downstream touch), base frame, mm; direction: +Y, the unit vector of travel;
    z_axis: the belt's normal (+Z), up; x = y cross z; camera_offset_mm: how far
    upstream of the origin the camera's line lies, along the belt; working_length_mm: the belt's
    working length (the span rule of the calibration); ticks_per_mm: the robot's own decoder's scale, where it
    was calibrated apart from the PLC's counter."""

    counter_bits: int
    counts_per_mm: float | None = None
    ticks_per_mm: float | None = None  # the robot's own decoder (UR), signed; None: it counts as the PLC's counter
    origin: tuple[float, float, float] | None = None
    direction: tuple[float, float, float] | None = None
    z_axis: tuple[float, float, float] | None = None
    camera_offset_mm: float | None = None
    working_length_mm: float | None = None
    pick: object = None  # [conveyor.pick]: codegen.kinds.conveyor.pick.Pick, or None (no pick program)

    @property
    def robot_ticks_per_mm(self) -> float | None:
        """The scale the robot's own decoder counts at: its own calibration, else the PLC's counter's."""
        return self.counts_per_mm if self.ticks_per_mm is None else self.ticks_per_mm

    def frame(self) -> np.ndarray | None:
        return None if self.origin is None else belt2base(self.origin, self.direction, self.z_axis)


def belt2base(origin, direction, z_axis) -> np.ndarray:
    """The belt frame (4x4): x = y cross z, y the direction of travel, z the belt's normal."""
    y, z = np.asarray(direction, dtype=float), np.asarray(z_axis, dtype=float)
    out = np.eye(4)
    out[:3, :3] = np.column_stack([np.cross(y, z), y, z])
    out[:3, 3] = origin
    return out


def parse_conveyor(ctx, data: dict, targets=(), pose_format: str = "xyzabc") -> Conveyor | None:
    """[conveyor]: its keys as declared (keys.py), then the rules between them; [conveyor.pick] once the belt
    is known calibrated."""
    if "conveyor" not in data:
        return None
    loader = Loader(ctx, pose_format)
    values = loader.table(CONVEYOR, data["conveyor"], "conveyor", readers={"pick": lambda raw, where: raw})
    if values["counts_per_mm"] is not None and abs(values["counts_per_mm"]) < 1e-3:
        ctx.fail("conveyor.counts_per_mm", "must be a signed scale of 0.001 to 1e6 counts per mm")
    if values["ticks_per_mm"] is not None and abs(values["ticks_per_mm"]) < 1e-3:
        ctx.fail("conveyor.ticks_per_mm", "must be a signed scale of 0.001 to 1e6 ticks per mm")
    if values["ticks_per_mm"] is not None and values["counts_per_mm"] is None:
        ctx.fail("conveyor.ticks_per_mm", "needs the belt calibrated: counts_per_mm (codegen calibrate conveyor)")
    frame_keys = [k for k in ("counts_per_mm", "origin", "direction", "z_axis") if values[k] is not None]
    if frame_keys and len(frame_keys) != 4:
        ctx.fail("conveyor", "counts_per_mm, origin, direction and z_axis come together (`codegen calibrate conveyor`)")
    if frame_keys:
        for key in ("direction", "z_axis"):
            if abs(math.hypot(*values[key]) - 1.0) > UNIT_TOL:
                ctx.fail(f"conveyor.{key}", "must be a unit vector")
        if abs(float(np.dot(values["direction"], values["z_axis"]))) > UNIT_TOL:
            ctx.fail("conveyor.z_axis", "must be at right angles to direction")
    if values["pick"] is not None:
        missing = [k for k in ("counts_per_mm", "camera_offset_mm") if values[k] is None]
        if missing:
            ctx.fail("conveyor.pick", f"needs the calibrated belt: {', '.join(missing)} (codegen calibrate conveyor)")
        values["pick"] = parse_pick(ctx, loader, values["pick"], targets)
        check_pick(ctx, values["counts_per_mm"], values["camera_offset_mm"], values["pick"])
        if values["ticks_per_mm"] is not None:
            check_pick(ctx, values["ticks_per_mm"], values["camera_offset_mm"], values["pick"], "ticks of the robot's")
    return build(Conveyor, values)


COUNTER_RANGE = 2**16  # the pick programs read a 16-bit count (codegen/sim/bus.py)


def check_pick(ctx, counts_per_mm: float, camera_offset_mm: float, pick, what: str = "counts of the") -> None:
    """What the programs need of the belt: the camera's line upstream of the window; a part's travel from
    it to the window's end within a quarter of the 16-bit counter (a difference is unwound once: a part
    taken as late again is still counted right); two counts of travel within the gripper's capture. what: whose
    counts (the PLC's counter, or the robot's own decoder's ticks: the same rules, its 16-bit filtered count)."""
    start, end = pick.window_mm
    if -camera_offset_mm >= start:
        ctx.fail("conveyor.pick.window_mm", f"must start downstream of the camera's line (y {-camera_offset_mm:g} mm)")
    counts = abs(counts_per_mm) * (camera_offset_mm + end)
    if counts > COUNTER_RANGE / 4:
        ctx.fail(
            "conveyor.pick.window_mm",
            f"the camera's line to the window's end is {counts:.0f} {what.split()[0]}; the programs' 16-bit count "
            f"allows {COUNTER_RANGE // 4}: bring the window closer to the camera",
        )
    if end - start < 2.0 / abs(counts_per_mm):
        ctx.fail(
            "conveyor.pick.window_mm",
            f"{end - start:g} mm wide, less than two {what} encoder ({2.0 / abs(counts_per_mm):.3g} mm): "
            "the programs could not tell a part inside it from one outside",
        )
    if 2.0 / abs(counts_per_mm) > pick.capture_mm:
        ctx.fail(
            "conveyor.pick.capture_mm",
            f"two {what} encoder ({2.0 / abs(counts_per_mm):.2f} mm) exceed the gripper's capture range",
        )


def conveyor_of(cell) -> Conveyor | None:
    """A cell's [conveyor], or None."""
    return cell.sections.get("conveyor")
