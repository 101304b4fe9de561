"""The guard every generated program runs before it moves: ranges, halt reasons, codes and messages."""

from __future__ import annotations

# Largest value a camera reading or a taught coordinate may have (mm). Beyond it the reading is
# treated like a non-finite one: no robot of this class reaches 100 m, and the bound keeps every
# float32 controller far from overflow.
READING_RANGE_MM = 100_000.0
READING_RANGE_DEG = 360.0
# Largest coordinate a taught pose or a calibration mark may have (mm): a float32 controller's step
# there is 0.001 mm, and the corrected poses stay within verify's 0.005 mm (measured 0.0016 mm at
# 9,999 mm; at 100,000 mm the error is 0.008 mm, beyond what verify accepts).
TAUGHT_RANGE_MM = 10_000.0
PIXEL_RANGE = 1_000_000.0  # a camera reading beyond this many pixels is treated as invalid

# Halt reasons, in the order the guard checks them.
UNKNOWN_STATION = "unknown_station"
INVALID_READING = "invalid_reading"
SHIFT_OVER_LIMIT = "shift_over_limit"
ROTATION_OVER_LIMIT = "rotation_over_limit"
NO_ANSWER = "no_answer"  # the vision PC did not answer the program's request in time (codegen.model.vision)
CONNECTION_LOST = "connection_lost"  # the channel to the vision PC lost its connection while the program waited
NO_FEEDBACK = "no_feedback"  # the work pose's signal was not confirmed in time (codegen.model.io)
NOT_RELEASED = "not_released"  # at the start, the work pose's signal released did not show (its feedback stays on)
NOT_AT_HOME = "not_at_home"  # the program was started with the arm away from home (restart = "at_home")
PART_HELD = "part_held"  # a station that takes a part first, started with one in the gripper
NO_PART = "no_part"  # a station that puts a part down first, started with none in the gripper

# The codes a program's guard function returns: 0 ok, then the reasons in the order they are checked.
GUARD_CODES = {INVALID_READING: 1, SHIFT_OVER_LIMIT: 2, ROTATION_OVER_LIMIT: 3}
UNKNOWN_STATION_TEXT = "unknown station id "  # the program appends the id it read


def no_answer_text(timeout_s: float) -> str:
    """The message of a program whose request the vision PC did not answer in time."""
    return f"no answer from the vision PC ({timeout_s:g} s per request)"


def reading_in_range(x: float, y: float, theta: float) -> bool:
    """Finite and inside the plausible range; NaN fails every comparison, as on a controller."""
    return abs(x) <= READING_RANGE_MM and abs(y) <= READING_RANGE_MM and abs(theta) <= READING_RANGE_DEG


def pixels_in_range(u: float, v: float, angle: float) -> bool:
    return abs(u) <= PIXEL_RANGE and abs(v) <= PIXEL_RANGE and abs(angle) <= READING_RANGE_DEG


# The stops that name no station: their messages from the cell's settings.
_CELL_MESSAGES = {
    NO_ANSWER: lambda cell: no_answer_text(cell.vision.timeout_s),
    CONNECTION_LOST: lambda cell: "the connection to the vision PC is lost: check its network, start again",
    NOT_AT_HOME: lambda cell: (
        f"start with the arm at home{' or a retreat' if cell.stations_section() is not None else ''} "
        f"(every joint within {cell.motion.start_tolerance_deg:g} deg)"
    ),
    NOT_RELEASED: lambda cell: f"the gripper did not release in {cell.io.timeout_s:g} s (its feedback stays on)",
    NO_FEEDBACK: lambda cell: f"no feedback from the gripper in {cell.io.timeout_s:g} s",
    PART_HELD: lambda cell: "the gripper holds a part this station cannot put down: take it out, start again",
    NO_PART: lambda cell: "the gripper holds no part to put down: give it its part, start again",
}


def halt_message(cell, reason: str, station_name: str | None, station_id: int) -> str:
    """The operator message every generated program shows when it halts (a contract); a reading over its limits:
    those of the section that carries the cell's stations."""
    if reason == UNKNOWN_STATION:
        return f"{UNKNOWN_STATION_TEXT}{station_id}"
    if reason in _CELL_MESSAGES:
        return _CELL_MESSAGES[reason](cell)
    name = station_name if station_name is not None else "?"
    if reason == INVALID_READING:
        return f"station {name}: invalid mark reading"
    if reason not in (SHIFT_OVER_LIMIT, ROTATION_OVER_LIMIT):
        raise ValueError(f"not a halt reason: {reason!r}")
    limits = cell.stations_section().limits
    if reason == SHIFT_OVER_LIMIT:
        return f"station {name}: mark shift over {limits.max_shift_mm:g} mm, recalibrate"
    return f"station {name}: mark rotation over {limits.max_rotation_deg:g} deg, recalibrate"
