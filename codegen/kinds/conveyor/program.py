"""Template variables of a pick-from-belt program: the belt frame and scale, the window, the part queue's names."""

from __future__ import annotations

import numpy as np

from codegen.emit import EmitError, Emitter, owned
from codegen.kinds.conveyor.facts import facts
from codegen.kinds.conveyor.section import conveyor_of
from codegen.model.cell import TaughtPose
from codegen.poses import zyx_deg_from_rotmat
from codegen.sim import bus

# the program's messages (the skip and stop texts verify reads back)
SKIPPED = "conveyor: skipped (past the window's end): part "
BAD_READING = "conveyor: a part outside x_range_mm or z_range_mm: check the camera"
STOPPED = "conveyor: the line stopped"
TOO_LATE = "conveyor: too late to intercept, skipped: part "  # an intercepting arm that arrived after the part
POLL_S = 0.012  # intercept: how often the program reads the encoder while the part comes (s)


def lead_seconds(cell) -> float:
    """How long before the part reaches the intercept point an intercepting arm starts down: the descent
    of approach_dz at the work speed, as the controller's straight move takes it (no acceleration in the
    interpreter's clock, nor in this lead: a real arm needs its measured descent time here), and the
    gripper's time to hold the part once its output is set (grip_s)."""
    pick = conveyor_of(cell).pick
    return pick.approach_dz / cell.motion.work_speed_mm_s + pick.grip_s


def conveyor_ident(cell, target) -> str:
    """The program's name ("cnv_" and the cell's name, as the target spells identifiers)."""
    return Emitter(target).identifier("cnv_", cell.name, "the conveyor program")


def conveyor_file_names(cell, target) -> list[str]:
    """The program's files, named as the program (some controllers require it of a module's files)."""
    ident = conveyor_ident(cell, target).lower()
    return [name.format(conveyor=ident) for name in facts(target).get("files", [])]


def picks_on(cell, target) -> bool:
    """Whether the cell has a pick program for this target ([conveyor.pick] tracking names it)."""
    pick = None if conveyor_of(cell) is None else conveyor_of(cell).pick
    if pick is None or target.name not in pick.tracking:
        return False
    if not facts(target).get("files"):
        raise EmitError(
            f"conveyor.pick.tracking.{target.name}: codegen has no conveyor tracking program for {target.title} yet"
        )
    return True


def _xyzabc(pose: np.ndarray) -> tuple[float, ...]:
    return tuple(float(v) for v in (*pose[:3, 3], *zyx_deg_from_rotmat(pose[:3, :3])))


def conveyor_context(cell, target, emitter) -> dict:
    """Numbers in the target's notation: the belt frame (belt2base), the direction of travel signed so
    that the encoder's ticks count along it, ticks per metre, counts per mm, the camera's line, the
    window, the ranges, the gripper's orientation on a part, the place and the registers' numbers."""
    belt, pick = conveyor_of(cell), conveyor_of(cell).pick
    number = emitter.number
    frame = belt.frame()
    e = belt.counts_per_mm
    sign = 1.0 if e > 0 else -1.0
    place = pick.place.matrix()
    above = place.copy()
    above[2, 3] += pick.approach_dz
    ident = emitter.identifier("cnv_", cell.name, "the conveyor program")
    return {
        "ident": ident,
        "frame": emitter.pose(TaughtPose("belt", _xyzabc(frame), "xyzabc")),
        "direction": [number(sign * v, 9) for v in belt.direction],
        "ticks_per_m": number(abs(e) * 1000.0, 6),
        "counts_per_mm": number(e, 9),
        "camera_y": number(-belt.camera_offset_mm, 4),
        "window": [number(v, 4) for v in pick.window_mm],
        "x_range": [number(v, 4) for v in pick.x_range_mm],
        "z_range": [number(v, 4) for v in pick.z_range_mm],
        "grip": emitter.pose(TaughtPose("grip", (0.0, 0.0, 0.0, *pick.tool_orientation), "xyzabc")),
        "approach_dz": number(pick.approach_dz, 4),
        "place": emitter.pose(pick.place),
        "place_above": emitter.pose(TaughtPose("place_above", _xyzabc(above), "xyzabc")),
        "encoder_inputs": [
            emitter.signal(v, f"conveyor.pick.encoder_inputs.{target.name}")
            for v in pick.encoder_inputs.get(target.name, ())
        ],
        "registers": owned(facts(target).get("registers")),  # UR
        "signals": owned(facts(target).get("signals")),  # signal groups (codegen/conveyor/bus.py)
        "group_offset": bus.OFFSET,  # x and z on a 16-bit group: raw = round(scale x) + offset
        "group_scale": number(bus.SCALE, 1),
        "counter_span": 2**bus.GROUP_BITS,  # the 16-bit count's range: a difference is unwound by it
        "counter_half": 2 ** (bus.GROUP_BITS - 1),
        "intercept": number(pick.intercept_mm, 4),  # intercept: the gripper meets the part here (belt y)
        "lead_s": number(lead_seconds(cell), 6),  # intercept: the descent's duration
        "poll_s": number(POLL_S, 3),
        "too_late": emitter.string(TOO_LATE),
        "skipped": emitter.string(SKIPPED),
        "bad_reading": emitter.string(BAD_READING),
        "stopped": emitter.string(STOPPED),
    }
