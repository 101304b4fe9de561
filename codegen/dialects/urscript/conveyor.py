"""URScript's encoder and conveyor tracking: the tick counts of a simulated belt, track_conveyor_linear's offset."""

# URScript Script Directory (e-Series), module motion: encoder_enable_pulse_decode, encoder_get_tick_count,
# encoder_unwind_delta_tick_count, track_conveyor_linear, stop_conveyor_tracking (sections 14.2-14.6, 14.43,
# 14.50). Facts used here:
# - encoder_index is 0 or 1; decoder_type 0 (none), 1 (quadrature), 2 (rising and falling edge on A),
#   3 (rising edge on A), 4 (falling edge on A); on the e-Series the A and B inputs "must be 8-11".
# - encoder_get_tick_count(index) returns the filtered count as a float in [0; 65536[ ("use caution when
#   subtracting encoder tick counts as it wraps around"); opt="raw" returns the int32 count.
# - encoder_unwind_delta_tick_count(index, delta) returns the delta as a float, assuming a wrap when it is
#   larger than half the encoder's range; nil when the encoder is not enabled.
# - track_conveyor_linear(direction, ticks_per_meter, encoder_index=0): "makes robot movement track a linear
#   conveyor"; direction is a pose vector in the base frame; ticks_per_meter the ticks per metre of travel.
#   The manual does not say from which tick count the offset is measured: UR's staff on the UR forum
#   ("Conveyer tracking theory under the hood") say the targets are where the part is when tracking starts,
#   and that the robot follows while it waits. Modelled so: offset(t) = (ticks(t) - ticks at the call) /
#   ticks_per_meter * direction, over every commanded pose and while the arm stands; the controller's
#   internal count does not wrap (the filtered count's wrap is the program's concern only).
# - stop_conveyor_tracking(a=20): stops following; the arm stays where the belt carried it.
# Assumed: direction is a unit vector (the manual does not say how another length is taken: refused here).

from __future__ import annotations

import math

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.ramp import travel_seconds
from codegen.dialects.core.values import RunError

FILTERED_RANGE = 65536  # encoder_get_tick_count: [0; 65536[
INT32 = 2**32
DECODERS = range(0, 5)
ENCODER_INPUTS = range(8, 12)  # e-Series
MM_PER_M = 1000.0


def _encoder(fr, index, where: str):
    """The simulated encoder wired to this index (a device of the run with encoder(index)), enabled."""
    index = int(index)
    if index not in (0, 1):
        raise RunError(f"{where}: encoder_index must be 0 or 1")
    enabled = fr.m.state.encoders.get(index)
    if not enabled:
        return None
    _decoder, a, b = enabled
    for device in fr.m.devices:
        belt = getattr(device, "encoder", lambda _i, _a, _b: None)(index, a, b)
        if belt is not None:
            return belt
    raise RunError(f"{where}: no encoder is wired to index {index} here (codegen verify attaches a simulated belt)")


class Tracking:
    """track_conveyor_linear's state: the direction (unit, base frame), ticks per metre, the belt and the
    unwrapped tick count at the call; the last commanded pose (moves are timed relative to the belt)."""

    def __init__(self, belt, direction: np.ndarray, ticks_per_m: float, start_ticks: int, last) -> None:
        self.belt, self.direction, self.ticks_per_m, self.start_ticks = belt, direction, ticks_per_m, start_ticks
        self.last_commanded = last  # the pose the arm was commanded to last (base frame at the start), or None

    def offset_mm(self, t: float) -> np.ndarray:
        return self.direction * ((self.belt.unwrapped_count(t) - self.start_ticks) / self.ticks_per_m * MM_PER_M)

    def shifted(self, pose: np.ndarray, t: float) -> np.ndarray:
        out = pose.copy()
        out[:3, 3] += self.offset_mm(t)
        return out

    def pose_now(self, machine) -> np.ndarray | None:
        return None if self.last_commanded is None else self.shifted(self.last_commanded, machine.clock)


def tracked_move(fr, event, speed_mm_s: float, where: str) -> float | None:
    """While tracking: the commanded pose is where the part was when tracking started; the arm ends the
    move at that pose moved by the belt's travel until then. Returns the move's duration (relative to the
    belt: the commanded distance over the speed), None when not tracking."""
    tracking = fr.m.tracking
    if tracking is None:
        return None
    if event.tcp2base is None:
        raise RunError(f"{where}: a move to joint positions while tracking a conveyor is not modelled")
    commanded = event.tcp2base
    seconds = travel_seconds(tracking.last_commanded, commanded, speed_mm_s)
    end = max(fr.m.clock, fr.m.arm_until) + seconds
    event.tcp2base = tracking.shifted(commanded, end)
    tracking.last_commanded = commanded
    return seconds


def builtins(pose_of, number_of) -> dict:
    """The encoder and tracking functions; pose_of and number_of: the dialect's argument checks."""

    def enable(fr, args, kwargs, where):
        if len(args) != 4:
            raise RunError(f"{where}: encoder_enable_pulse_decode(encoder_index, decoder_type, A, B)")
        index, decoder, a, b = (int(number_of(v, where, "argument")) for v in args)
        if index not in (0, 1) or decoder not in DECODERS:
            raise RunError(f"{where}: encoder_index 0 or 1, decoder_type 0..4")
        if decoder and (a not in ENCODER_INPUTS or b not in ENCODER_INPUTS):
            raise RunError(f"{where}: the encoder's A and B inputs must be 8..11 (e-Series)")
        # the decoder and which inputs the program takes as A and B: swapped against the wiring, it counts backwards
        fr.m.state.encoders[index] = (decoder, a, b) if decoder else None

    def get_tick_count(fr, args, kwargs, where):
        belt = _encoder(fr, args[0] if args else kwargs.get("encoder_index", 0), where)
        if belt is None:
            raise RunError(f"{where}: encoder {args[0] if args else 0} is not enabled (encoder_enable_pulse_decode)")
        ticks = belt.unwrapped_count(fr.m.clock)
        if kwargs.get("opt", args[1] if len(args) > 1 else "") == "raw":
            return (ticks + INT32 // 2) % INT32 - INT32 // 2
        return float(ticks % FILTERED_RANGE)

    def unwind(fr, args, kwargs, where):
        if len(args) != 2:
            raise RunError(f"{where}: encoder_unwind_delta_tick_count(encoder_index, delta_tick_count)")
        if _encoder(fr, args[0], where) is None:
            return None  # "will always return nil" when the encoder is not enabled
        delta = float(number_of(args[1], where, "delta_tick_count"))
        if delta > FILTERED_RANGE / 2:
            delta -= FILTERED_RANGE
        elif delta < -FILTERED_RANGE / 2:
            delta += FILTERED_RANGE
        return delta

    def track_linear(fr, args, kwargs, where):
        direction = pose_of(args[0] if args else kwargs.get("direction"), where)
        tpm = float(number_of(args[1] if len(args) > 1 else kwargs.get("ticks_per_meter"), where, "ticks_per_meter"))
        index = args[2] if len(args) > 2 else kwargs.get("encoder_index", 0)
        values = [float(v) for v in direction.values()]
        posemath.check_finite(tuple(values), where, "direction")
        if abs(math.hypot(*values[:3]) - 1.0) > 1e-4:
            raise RunError(f"{where}: track_conveyor_linear direction must be a unit vector (base frame)")
        if not tpm > 0 or not math.isfinite(tpm):
            raise RunError(f"{where}: ticks_per_meter must be positive")
        belt = _encoder(fr, index, where)
        if belt is None:
            raise RunError(f"{where}: encoder {index} is not enabled (encoder_enable_pulse_decode)")
        last = fr.m.tool_pose()
        fr.m.tracking = Tracking(belt, np.array(values[:3]), tpm, belt.unwrapped_count(fr.m.clock), last)

    def stop_tracking(fr, args, kwargs, where):
        tracking = fr.m.tracking
        if tracking is not None:  # the arm stays where the belt carried it
            fr.m._last_tcp2base = tracking.pose_now(fr.m)
            fr.m.tracking = None

    return {
        "encoder_enable_pulse_decode": enable,
        "encoder_get_tick_count": get_tick_count,
        "encoder_unwind_delta_tick_count": unwind,
        "track_conveyor_linear": track_linear,
        "stop_conveyor_tracking": stop_tracking,
    }
