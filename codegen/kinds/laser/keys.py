"""The laser kind's part of the cell file: the [laser] table (source 003's two-beam sensor station)."""

from __future__ import annotations

from codegen.controllers import get_target, target_names
from codegen.guard import TAUGHT_RANGE_MM
from codegen.model.io import signals
from codegen.model.motion import SPEED_MIN_MM_S
from codegen.model.schema import Key, KindKeys, Table

RUNS_MAX = 10  # runs of the measurement in one program (each about half a minute of motion)
PIN_MIN_MM = 0.2  # a pin thinner than this is no target for the beams (and the reference's scan steps 0.1 mm)


def _length(doc: str, default: float, high: float) -> Key:
    return Key("number", doc, unit="mm", low=0.0, open_low=True, high=high, default=default)


def _speed(doc: str, default: float, high: float) -> Key:
    """A TCP speed of the procedure: at least the programs' least speed (as [cell.motion]'s)."""
    return Key("number", doc, unit="mm/s", low=SPEED_MIN_MM_S, high=high, default=default)


TOOL_PATTERN = r"[A-Za-z][A-Za-z0-9_]*"  # a production tool's name (the section also refuses the language's words)


def _production_tool(target: str) -> Key | None:
    """A target's production tool as its [program.laser] production_tool has it: a number or a name."""
    spec = get_target(target).kind_tables.get("laser", {}).get("production_tool")
    if spec is None:
        return None
    if spec["form"] == "number":
        return Key("integer", f"the {target} controller's tool number", low=1, high=spec["max"], controllers=target)
    return Key("string", f"the name of the {target} production tool's data", pattern=TOOL_PATTERN, controllers=target)


def _production_tools() -> Key:
    tools = {t: key for t in target_names() if (key := _production_tool(t)) is not None}
    return Key(
        "map",
        "the production tool the TCP found goes into, per target (else [cell.tool] numbered where the target has it)",
        names=tuple(tools),
        per_name=tools,
        controllers=", ".join(tools),
    )


LASER = Table(
    "The two-beam laser sensor station that measures the tool's TCP with a pin.",
    {
        "sensor_frame": Key(
            "pose",
            "S in the base frame: the beams' plane is its xy-plane, crossing at its origin",
            count=(6, 7),
            required=True,
            low=-TAUGHT_RANGE_MM,
            high=TAUGHT_RANGE_MM,
        ),
        "pin_radius_mm": Key(
            "number",
            "the calibrated pin's radius (a thinner pin is no target for the beams)",
            unit="mm",
            low=PIN_MIN_MM,
            high=25.0,
            default=1.0,
        ),
        "circle_mm": _length("the circles' radius", 10.0, 100.0),
        "depths_mm": Key(
            "numbers",
            "the guessed tip below the beams' plane on each circle [d1, d2]",
            unit="mm",
            count=2,
            low=0.0,
            open_low=True,
            high=200.0,
            default=(5.0, 15.0),
        ),
        "clearance_mm": _length("the tip search starts this far above the plane and ends as far below", 10.0, 200.0),
        "offset_max_mm": _length("how far the true tip and axis may lie from [cell.tool]", 3.0, 50.0),
        "circle_speed_mm_s": _speed("the TCP's speed on the circles", 10.0, 250.0),
        "search_speed_mm_s": _speed("the TCP's speed in the tip search", 2.0, 50.0),
        "beam_x": signals("beam X's switching output, per target (an input number or name)", required=True),
        "beam_y": signals("beam Y's switching output, per target (an input number or name)", required=True),
        "production_tool": _production_tools(),
        "runs": Key(
            "integer",
            "how many times the program measures the TCP (circles and search) before it writes their mean",
            low=1,
            high=RUNS_MAX,
            default=3,
        ),
        "spread_max_mm": _length(
            "the runs' TCPs may lie this far from their mean (at most offset_max_mm); farther: not written",
            0.1,
            50.0,
        ),
        "safe_height_mm": _length(
            "the safe pose's height above the beams' plane, straight above the circles' start (at least "
            "clearance_mm + offset_max_mm)",
            100.0,
            1000.0,
        ),
        "reference_tcp_mm": Key(
            "numbers",
            "the reference pin's TCP in the flange frame [x, y, z], known better than the calibration's goal, its "
            "axis along the flange's z: given, codegen writes the setup program that measures the sensor frame",
            unit="mm",
            count=3,
            low=-TAUGHT_RANGE_MM,
            high=TAUGHT_RANGE_MM,
        ),
        "reference_radius_mm": Key(
            "number",
            "the reference pin's radius (its end face is flat and square to its axis)",
            unit="mm",
            low=PIN_MIN_MM,
            high=25.0,
            default=1.5,
        ),
    },
)
KEYS = KindKeys(tables={"laser": Key("table", LASER.doc, table=LASER)})
