"""Template variables of a pick-from-belt program: the belt frame and scale, the window, the part queue's names,
the payload while a part is held, the way home, the place's interlock."""

from __future__ import annotations

import math

import numpy as np

from codegen.emit import Code, EmitError, Emitter, owned
from codegen.kinds.conveyor import native
from codegen.kinds.conveyor.kind import KIND
from codegen.kinds.conveyor.plan import blends, carried_load, part_load
from codegen.kinds.conveyor.section import conveyor_of
from codegen.kinds.conveyor.timing import (
    POLL_S,
    SPEED_READS,
    SPEED_WINDOW_S,
    descent_seconds,
    lead_parts,
    lead_seconds,
    path_acc_mm_s2,
)
from codegen.model.cell import TaughtPose
from codegen.model.io import POLL_S as IO_POLL_S
from codegen.poses import FORMAT_DECIMALS, native_values, rotmat_from_zyx_deg, zyx_deg_from_rotmat
from codegen.render import inertia_literal
from codegen.sim import bus

# the program's messages (the skip and stop texts verify reads back)
SKIPPED = "conveyor: skipped (past the window's end): part "
BAD_READING = "conveyor: a part outside x_range_mm or z_range_mm: check the camera"
STOPPED = "conveyor: the line stopped"
TOO_LATE = "conveyor: too late to intercept, skipped: part "  # an intercepting arm that arrived after the part
TOO_CLOSE = "conveyor: too close to the part before, skipped: part "  # ABB native: the queue did not take it
LOST = "conveyor: lost from the start window, skipped: part "  # ABB native: WaitWObj's error handler
PUT_DOWN = "conveyor: a part held at the start: put down at the place"
EARLY = "conveyor: seen before the program started, skipped: part "  # UR: no count of its own encoder for it
STANDS = "conveyor: the belt stands, the arm waits above it: part "  # the encoder still while a part is on its way
FLUSHED = "conveyor: queued before the start, skipped: part "  # ABB native: the unit's queue emptied at the start
NOT_HELD = "conveyor: the gripper did not hold it, skipped: part "  # ABB native: left on the belt, the arm off it
NOT_OPENED = "conveyor: the gripper did not release the part it failed to grip"  # its stop, once off the belt
# ABB native: the unit's queue and the PLC's disagree (no object for the part, or another part's): its stop
OUT_OF_STEP = "conveyor: the unit's queue is out of step with the PLC's: empty both, restart"
# UR: the robot's own latched count and the PLC's queue disagree (no latch within PAIR_MM of a part seen since the
# start, or the two counts apart by more than that once the part reaches the window: a trigger the robot missed, its
# decoder counting another scale than the PLC's counter the belt was calibrated with): its stop
MISMATCH = "conveyor: the robot's encoder and the PLC's count disagree: check the trigger and the scale"
# UR: more trigger pulses latched and not yet paired than its ring holds (a chattering trigger): the oldest overwritten
LATCH_RING = 32  # UR: the trigger's latched counts the program keeps (CNV_RING)
OVERRUN = "conveyor: more trigger pulses pending than the latch ring holds: check the trigger"
PAIR_MM = 10.0  # UR: a count latched at the trigger and the PLC's copy agree within this for one part (mm)
MASS_DECIMALS = 3
# intercept: a part left on the belt this much further past the gripper's reach (its radius) before the arm comes down
# near it: the count's rounding and the part's place on the belt as the camera reports it
PASSED_MARGIN_MM = 10.0


def place_blocked(cell) -> str:
    """The stop of a program whose place did not come clear in time."""
    return f"the place is not clear after {conveyor_of(cell).pick.place_timeout_s:g} s"


def no_part(cell) -> str:
    """The notification of a wait for the next part that lasted no_part_s (the program goes on waiting)."""
    return f"conveyor: no part for {conveyor_of(cell).pick.no_part_s:g} s, still waiting"


def reads(seconds: float) -> int:
    """How many reads POLL_S apart make this long (the waits for a part and for the belt count their reads)."""
    return math.ceil(seconds / POLL_S - 1e-9)


def down_fixed_seconds(cell) -> float:
    """Intercept: the first stage's time besides its descent (from z_range_mm's top to the part's own approach height,
    which the program works out per part): the arm's start (motion_start_s, its longest), the belt's speed measured
    afresh at the part's approach height (SPEED_WINDOW_S) and two reads of the encoder (the read that finds the part
    due, one to spare)."""
    return conveyor_of(cell).pick.motion_start_s[1] + SPEED_WINDOW_S + 2 * POLL_S


def drift_mm(cell, target) -> float:
    """Intercept: how much sooner than the first stage predicts the part may arrive (mm): the belt's speed change
    (belt_accel_mm_s2) over the first stage, its speed half its window and a read old and changing on
    over the stage's horizon (the lead, down_fixed_seconds, the descent from z_range_mm's top to its bottom and the
    count's age: its longest), as the timing budget counts it over the lead. The first stage comes down this much
    earlier, so that a belt speeding up does not leave the descent onto the part too late."""
    pick = conveyor_of(cell).pick
    span = pick.z_range_mm[1] - pick.z_range_mm[0]
    horizon = lead_seconds(cell, target) + down_fixed_seconds(cell) + descent_seconds(cell, target, span)
    horizon += pick.count_latency_s[1]
    age = POLL_S + 0.5 * SPEED_WINDOW_S  # a speed over the last SPEED_READS reads, taken at the next read
    return pick.belt_accel_mm_s2 * (age * horizon + 0.5 * horizon**2)


def passed_parts(cell) -> tuple[float, float, float]:
    """Intercept: how far past the intercept point a part left on the belt must be before the arm comes down below the
    clear height for the next part (mm): half the part's length along the belt (part_size_mm's box turned by
    tool_orientation; without it, half min_gap_mm: parts that close do not overlap), the tool's radius and
    PASSED_MARGIN_MM."""
    pick = conveyor_of(cell).pick
    if pick.part_size_mm is not None:
        along = np.abs(rotmat_from_zyx_deg(*pick.tool_orientation))[1] @ np.asarray(pick.part_size_mm, dtype=float)
        half = 0.5 * float(along)
    else:
        half = 0.5 * pick.min_gap_mm
    radius = cell.robot.tool.radius_mm if cell.robot is not None else 0.0
    return half, float(radius), PASSED_MARGIN_MM


def conveyor_ident(cell, target) -> str:
    """The program's name ("cnv_" and the cell's name, as the target spells identifiers)."""
    return Emitter(target).identifier("cnv_", cell.name, "the conveyor program")


def data_ident(cell, target, emitter: Emitter | None = None) -> str:
    """The module that keeps the belt program's tool where a program load does not reach it (RAPID's system module)."""
    emitter = emitter or Emitter(target)
    return emitter.identifier("cnv_", f"{cell.name}_data", "the conveyor program's data module")


def tool_ident(cell, target, emitter: Emitter) -> str:
    """The belt program's tool where the program's data module declares it (one per cell: the task's global name;
    a signal of the cell's named so is refused)."""
    return emitter.identifier("cnv_", f"{cell.name}_tool", "the conveyor program's tool")


def conveyor_file_names(cell, target) -> list[str]:
    """The program's files, named as the program (some controllers require it of a module's files)."""
    ident, data = conveyor_ident(cell, target).lower(), data_ident(cell, target).lower()
    return [name.format(conveyor=ident, data=data) for name in KIND.facts(target).get("files", [])]


def picks_on(cell, target) -> bool:
    """Whether the cell has a pick program for this target ([conveyor.pick] tracking names it)."""
    pick = None if conveyor_of(cell) is None else conveyor_of(cell).pick
    if pick is None or target.name not in pick.tracking:
        return False
    if not KIND.facts(target).get("files"):
        raise EmitError(
            f"conveyor.pick.tracking.{target.name}: codegen has no conveyor tracking program for {target.title} yet"
        )
    return True


def _xyzabc(pose: np.ndarray) -> tuple[float, ...]:
    return tuple(float(v) for v in (*pose[:3, 3], *zyx_deg_from_rotmat(pose[:3, :3])))


def safe_belt(cell) -> tuple[float, float, float]:
    """The safe pose above the belt on the way home (belt frame, mm): above the window's start at the near edge of
    x_range_mm, approach_dz above the highest part (a pose the reach proof covers)."""
    pick = conveyor_of(cell).pick
    return pick.x_range_mm[0], pick.window_mm[0], pick.z_range_mm[1] + pick.approach_dz


def _point(emitter, target, values) -> list[str]:
    """Three coordinates (mm) in the target's unit (UR: m)."""
    native3 = native_values((*values, 0.0, 0.0, 0.0), "xyzabc", target.pose_format)[:3]
    return [emitter.number(v, d) for v, d in zip(native3, FORMAT_DECIMALS[target.pose_format][:3], strict=True)]


def _payload(cell, target, emitter) -> dict | None:
    """The part (mass, centre of gravity and inertia in the tool frame: a payload's load data) and the tool with the
    part (mass, centre of gravity and inertia in the flange frame: a load at the flange)."""
    robot = cell.robot
    if robot is None or target.name not in robot.arms:
        return None
    part, held = part_load(cell), carried_load(cell)
    return {
        "part_mass": emitter.number(part.mass, MASS_DECIMALS),
        "part_cog": _point(emitter, target, part.cog_mm),
        "part": inertia_literal(part, emitter),
        "mass": emitter.number(held.mass, MASS_DECIMALS),
        "cog": _point(emitter, target, held.cog_mm),
        "held": inertia_literal(held, emitter),
    }


def _signal(emitter, value, origin: str) -> Code | None:
    """A digital input as the cell names it: a number, or a configured signal's name (never a word of the language
    or one of the program's own names)."""
    return None if value is None else emitter.signal(value, origin)


def conveyor_context(cell, target, emitter) -> dict:
    """Numbers in the target's notation: the belt frame (belt2base), the direction of travel signed so
    that the encoder's ticks count along it, ticks per metre, counts per mm, the camera's line, the
    window, the ranges, the gripper's orientation on a part, the place and the registers' numbers, the
    payloads, the safe pose, the blends, the native tracking's configuration (ABB)."""
    belt, pick = conveyor_of(cell), conveyor_of(cell).pick
    number = emitter.number
    frame = belt.frame()
    e, ticks = belt.counts_per_mm, belt.robot_ticks_per_mm
    sign = 1.0 if ticks > 0 else -1.0  # the robot's own decoder's: track_conveyor_linear counts its ticks
    place = pick.place.matrix()
    above = place.copy()
    above[2, 3] += pick.approach_dz
    ident = emitter.identifier("cnv_", cell.name, "the conveyor program")
    mode = pick.tracking[target.name]
    timeout = pick.place_timeout_s
    out = {
        "ident": ident,
        "data_ident": data_ident(cell, target, emitter),
        "tool": tool_ident(cell, target, emitter),
        "mode": mode,
        "native": mode == "native",
        "frame": emitter.pose(TaughtPose("belt", _xyzabc(frame), "xyzabc")),
        "direction": [number(sign * v, 9) for v in belt.direction],
        "ticks_per_m": number(abs(ticks) * 1000.0, 6),
        "ticks_per_mm": number(ticks, 9),
        "own_scale": belt.ticks_per_mm is not None,  # UR: the robot's decoder calibrated on its own (--ticks)
        "counts_per_mm": number(e, 9),
        "camera_y": number(-belt.camera_offset_mm, 4),
        "window": [number(v, 4) for v in pick.window_mm],
        "x_range": [number(v, 4) for v in pick.x_range_mm],
        "z_range": [number(v, 4) for v in pick.z_range_mm],
        "grip": emitter.pose(TaughtPose("grip", (0.0, 0.0, 0.0, *pick.tool_orientation), "xyzabc")),
        "approach_dz": number(pick.approach_dz, 4),
        "overtravel": number(pick.overtravel_mm, 4),
        "place": emitter.pose(pick.place),
        "place_above": emitter.pose(TaughtPose("place_above", _xyzabc(above), "xyzabc")),
        "safe": [number(v, 4) for v in safe_belt(cell)],
        "encoder_inputs": [
            emitter.signal(v, f"conveyor.pick.encoder_inputs.{target.name}")
            for v in pick.encoder_inputs.get(target.name, ())
        ],
        "registers": owned(KIND.facts(target).get("registers")),  # UR
        "signals": owned(KIND.facts(target).get("signals")),  # signal groups (codegen/sim/bus.py)
        "group_offset": bus.OFFSET,  # x and z on a 16-bit group: raw = round(scale x) + offset
        "group_scale": number(bus.SCALE, 1),
        "counter_span": 2**bus.GROUP_BITS,  # the 16-bit count's range: a difference is unwound by it
        "counter_half": 2 ** (bus.GROUP_BITS - 1),
        "intercept": number(pick.intercept_mm, 4),  # intercept: the gripper meets the part here (belt y)
        "lead_s": number(lead_seconds(cell, target), 6),  # intercept: the descent's duration and the latencies' middles
        "lead_parts": [number(v, 6) for v in lead_parts(cell, target)],  # intercept: descent, hold, planning
        "down_s": number(down_fixed_seconds(cell), 6),  # intercept: the first stage's time but its descent
        "drift_mm": number(drift_mm(cell, target), 4),  # intercept: the first stage this much earlier (a speeding belt)
        "passed_mm": number(sum(passed_parts(cell)), 4),  # intercept: a part left on the belt this far past first
        "passed_parts": [number(v, 4) for v in passed_parts(cell)],
        "path_acc": None if path_acc_mm_s2(target) is None else number(path_acc_mm_s2(target) / 1000.0, 3),
        "timer": pick.timer.get(target.name),  # intercept: the controller's timer the speed is measured over
        "latency_s": number(pick.mean("count_latency_s"), 6),  # intercept: the count's age, its middle
        "poll_s": number(POLL_S, 3),
        "speed_window_s": number(SPEED_WINDOW_S, 3),
        "speed_reads": SPEED_READS,  # intercept: the reads the belt's speed is measured over (a ring of them)
        "payload": _payload(cell, target, emitter),
        "blend": blends(cell, target, mode),
        "place_clear": _signal(emitter, pick.place_clear.get(target.name), f"conveyor.pick.place_clear.{target.name}"),
        "place_timeout_s": number(timeout, 3),
        "zone_output": _signal(emitter, pick.zone_output.get(target.name), f"conveyor.pick.zone_output.{target.name}"),
        "place_polls": number(math.ceil(timeout / IO_POLL_S - 1e-9), 0),  # looks at it, as at the gripper's sensor
        "too_late": emitter.string(TOO_LATE),
        "skipped": emitter.string(SKIPPED),
        "bad_reading": emitter.string(BAD_READING),
        "stopped": emitter.string(STOPPED),
        "put_down": emitter.string(PUT_DOWN),
        "too_close": emitter.string(TOO_CLOSE),
        "early": emitter.string(EARLY),
        "mismatch": emitter.string(MISMATCH),
        "overrun": emitter.string(OVERRUN),
        "latch_ring": LATCH_RING,
        "pair_mm": number(PAIR_MM, 1),
        "wrap_m": number(2**15 / abs(ticks) / 1000.0, 1),  # UR: half the robot's count's wrap, as belt travel
        "lost": emitter.string(LOST),
        "not_held": emitter.string(NOT_HELD),
        "not_opened": emitter.string(NOT_OPENED),
        "flushed": emitter.string(FLUSHED),
        "out_of_step": emitter.string(OUT_OF_STEP),
        "place_blocked": emitter.string(place_blocked(cell)),
        "no_part": emitter.string(no_part(cell)),
        "no_part_s": number(pick.no_part_s, 3),
        "no_part_polls": reads(pick.no_part_s),  # reads of the queue, CNV_POLL apart: the wait's message
        "stands": emitter.string(STANDS),
        "belt_stop_s": number(pick.belt_stop_s, 3),
        "stand_polls": reads(pick.belt_stop_s),  # reads of the encoder without a count: the belt stands
    }
    if mode == "native":
        out.update(native.context(cell, target, emitter))
    return out
