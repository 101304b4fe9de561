"""The conveyor kind's part of the cell file: [conveyor] (the calibrated belt) and [conveyor.pick]."""

from __future__ import annotations

from codegen.controllers import get_target, target_names
from codegen.guard import TAUGHT_RANGE_MM
from codegen.kinds.conveyor.kind import KIND
from codegen.model.io import signals
from codegen.model.schema import Key, KindKeys, Table

MAX_MM = 10_000.0
# "native": the controller's own conveyor tracking (UR track_conveyor_linear, ABB's Conveyor Tracking option);
# "intercept": the arm waits above a point of the belt and comes down as the part arrives there (targets/<t>.toml
# [program.conveyor] tracking: what codegen writes for the controller)
TRACKING = ("native", "intercept")
COUNTER_BITS = (16, 24, 32)
_INTERVAL = {"type": "numbers", "unit": "mm", "count": 2, "low": -MAX_MM, "high": MAX_MM}
_VECTOR = {"type": "numbers", "count": 3}


def _seconds(doc: str, top: float) -> Key:
    """A duration as a number or as [least, most] (s), within [0, top]."""
    return Key(
        "either",
        doc,
        unit="s",
        default=0.0,
        alternatives=(
            Key("number", "a duration", unit="s", low=0.0, high=top),
            Key("numbers", "[least, most]", unit="s", count=2, low=0.0, high=top),
        ),
    )


def _facts(target: str) -> dict:
    return KIND.facts(get_target(target))


def _per_target(doc: str, fact: str, value, any_name: bool = False, values: Key | None = None) -> Key:
    """A value for each controller whose facts (targets/<t>.toml [program.conveyor]) have `fact` (value(target): its
    Key, from those facts); any_name: other names allowed too (values: theirs), for the section to say why not."""
    targets = tuple(t for t in target_names() if _facts(t).get(fact))
    return Key(
        "map",
        doc,
        names=None if any_name else targets,
        per_name={t: value(t) for t in targets},
        values=values,
        controllers=", ".join(targets),
    )


def _encoder_pair(target: str) -> Key:
    low, high = _facts(target)["encoder_inputs"]
    return Key("list", f"A and B on {target}", count=2, values=Key("integer", "a digital input", low=low, high=high))


def _trigger(target: str) -> Key:
    low, high = get_target(target).program["signals"]["range"]
    return Key("integer", f"a digital input of {target}", low=low, high=high)


PICK = Table(
    "Where parts are picked from the tracked belt and put down, and per target how (needs the calibrated belt).",
    {
        "window_mm": Key(**_INTERVAL, required=True, doc="the tracking window along the belt [start, end] (belt y)"),
        "x_range_mm": Key(**_INTERVAL, required=True, doc="where a part may lie across the belt [low, high]"),
        "z_range_mm": Key(**_INTERVAL, default=(0.0, 100.0), doc="a part's top above the belt [low, high]"),
        "tool_orientation": Key(
            "numbers",
            "a, b, c of the gripper at a part in the belt frame (Z-Y-X)",
            unit="deg",
            count=3,
            low=-360.0,
            high=360.0,
            default=(0.0, 0.0, 180.0),
        ),
        "approach_dz": Key(
            "number",
            "the gripper comes down onto the part and the place from this far above",
            unit="mm",
            low=0.0,
            open_low=True,
            high=1000.0,
            default=60.0,
        ),
        "overtravel_mm": Key(
            "number",
            "the gripper comes down this far past the part's top (a suction cup pressed on, its lip compressed: the "
            "seal holds on a part a little lower or tilted)",
            unit="mm",
            low=0.0,
            high=20.0,
            default=2.0,
        ),
        "place": Key(
            "pose",
            "where the parts go, base frame, in the cell's pose format",
            count=(6, 7),
            required=True,
            low=-TAUGHT_RANGE_MM,
            high=TAUGHT_RANGE_MM,
        ),
        "tracking": Key(
            "map",
            "per target of the cell, how it follows the belt",
            required=True,
            non_empty=True,
            values=Key("string", "how the target follows the belt", choices=TRACKING),
        ),
        "encoder_inputs": _per_target(
            "per target tracking natively on its own inputs: the encoder's A and B inputs",
            "encoder_inputs",
            _encoder_pair,
            any_name=True,  # a target of the cell that reads no encoder is told why (pick.py)
            values=Key("list", "[A, B]", count=2, values=Key("integer", "a digital input")),
        ),
        "trigger_input": _per_target(
            "per target that needs it: the digital input the camera's trigger is wired to", "trigger", _trigger
        ),
        "intercept_mm": Key(
            "number", "intercept: where along the belt the gripper meets the part (in the window)", unit="mm"
        ),
        "capture_mm": Key(
            "number",
            "intercept: how far off the gripper may meet the part and still hold it",
            unit="mm",
            low=0.0,
            open_low=True,
            high=50.0,
            default=3.0,
        ),
        "grip_s": _seconds("from the gripper's output to its hold on the part", 2.0),
        "belt_speed_max_mm_s": Key(
            "number", "the fastest the belt runs", unit="mm/s", low=1e-3, high=5000.0, default=200.0
        ),
        "belt_accel_mm_s2": Key(
            "number", "the fastest the belt's speed changes", unit="mm/s2", low=0.0, high=100_000.0, default=0.0
        ),
        "count_latency_s": _seconds("intercept: the count's age when the program reads it", 1.0),
        "motion_start_s": _seconds(
            "intercept: the program's planning time, from its last read of the encoder to the arm moving", 1.0
        ),
        "part_mass_kg": Key(
            "number",
            "the part: the payload while the gripper holds it",
            unit="kg",
            low=0.0,
            open_low=True,
            high=1000.0,
            required=True,
        ),
        "part_cog_mm": Key(
            "numbers",
            "the part's centre of gravity in the tool frame",
            unit="mm",
            count=3,
            low=-2000.0,
            high=2000.0,
            default=(0.0, 0.0, 0.0),
        ),
        "part_size_mm": Key(
            "numbers",
            "the part as a box along the tool frame's axes: its moments of inertia (none: a point mass)",
            unit="mm",
            count=3,
            low=0.0,
            open_low=True,
            high=5000.0,
        ),
        "place_clear": signals("per target, the input that says the place is free (none: the program does not ask)"),
        "zone_output": signals(
            "per target, the output on while the arm is over the belt below the clear height: the PLC stops the belt "
            "whenever the robot stops while it is on (none: the program sets none)"
        ),
        "place_timeout_s": Key(
            "number", "how long the program waits for place_clear", unit="s", low=0.2, high=600.0, default=10.0
        ),
        "no_part_s": Key(
            "number",
            "how long the program waits for the next part before it says none came (it goes on waiting)",
            unit="s",
            low=1.0,
            high=3600.0,
            default=30.0,
        ),
        "belt_stop_s": Key(
            "number",
            "how long the encoder may stand still while a part is on its way before the program says the belt "
            "stands (the arm waits above the belt)",
            unit="s",
            low=0.5,
            high=600.0,
            default=2.0,
        ),
        "min_gap_mm": Key(
            "number",
            "how close a part may follow the one before and still be picked (ABB native: the unit's Sync Separation)",
            unit="mm",
            low=0.0,
            default=0.0,
        ),
        "timer": _per_target(
            "per intercepting target that needs it: the controller's timer ($TIMER[n]) the program measures the "
            "belt's speed over (one no other program uses)",
            "timers",
            lambda t: Key("integer", f"a timer's number on {t}", low=1, high=_facts(t)["timers"]),
        ),
        "unit": _per_target(
            "per target that needs it (ABB native): the belt's mechanical unit",
            "unit",
            lambda t: Key("string", f"a conveyor's mechanical unit on {t}", choices=tuple(_facts(t)["units"])),
        ),
        "unit_position_check": Key(
            "boolean",
            "a target with a mechanical unit (ABB native): after WaitWObj, check the connected object's position (the "
            "unit's joint by CJointT, assumed mm since its sync) against the part's travel by the PLC's count, and "
            "stop when they disagree; false only for a first commissioning run, until that position is confirmed "
            "(the program's header says the check is off)",
            default=True,
        ),
        "unit_axis": _per_target(
            "per target that needs it (ABB native): the unit's logical axis, where its position stands in every "
            "robtarget and jointtarget (7: eax_a ... 12: eax_f; default the target's facts: targets/<t>.toml)",
            "unit",
            lambda t: Key("integer", "a logical axis", low=7, high=12),
        ),
    },
)
CONVEYOR = Table(
    "The belt: its encoder's scale, its frame and the camera's offset (`codegen calibrate conveyor` writes them).",
    {
        "counter_bits": Key("integer", "the encoder counter's width", choices=COUNTER_BITS, default=32),
        "counts_per_mm": Key(
            "number", "encoder counts per mm of travel, signed (|value| 0.001 to 1e6)", low=-1e6, high=1e6
        ),
        "ticks_per_mm": Key(
            "number",
            "the robot's own decoder's ticks per mm of travel, signed (|value| 0.001 to 1e6; `codegen calibrate "
            "conveyor --ticks`): the scale a UR program tracks by; default counts_per_mm (the PLC's counter)",
            low=-1e6,
            high=1e6,
        ),
        "origin": Key(
            "numbers",
            "the belt frame's origin (the downstream touch), base frame",
            unit="mm",
            count=3,
            low=-TAUGHT_RANGE_MM,
            high=TAUGHT_RANGE_MM,
        ),
        "direction": Key(**_VECTOR, doc="the unit vector of travel (the belt frame's +y)"),
        "z_axis": Key(**_VECTOR, doc="the belt's normal, up (the belt frame's +z)"),
        "camera_offset_mm": Key("number", "how far upstream of the origin the camera's line lies", unit="mm"),
        "working_length_mm": Key(
            "number", "the belt's working length", unit="mm", low=0.0, open_low=True, high=100_000.0
        ),
        "pick": Key("table", PICK.doc, table=PICK),
    },
)
KEYS = KindKeys(tables={"conveyor": Key("table", CONVEYOR.doc, table=CONVEYOR)}, reads=("io",))
