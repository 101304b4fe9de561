"""The pallet kind's part of the cell file: the [[pallet]] tables."""

from __future__ import annotations

from dataclasses import replace

from codegen.controllers import get_target, target_names
from codegen.guard import TAUGHT_RANGE_MM
from codegen.model import robot
from codegen.model.io import signal_key, signals
from codegen.model.schema import Key, KindKeys, Table

MAX_LAYERS = 200
MAX_SIZE_MM = 5000.0
TIMEOUT_S = 10.0  # how long a program waits for an interlock input before it stops with a message
FAMILIES = ("column", "interlock", "pinwheel", "split-row")
_POINT = {
    "type": "numbers",
    "unit": "mm",
    "count": 3,
    "low": -TAUGHT_RANGE_MM,
    "high": TAUGHT_RANGE_MM,
    "required": True,
}
_OFFSET = {"type": "numbers", "unit": "mm", "count": 3, "low": -MAX_SIZE_MM, "high": MAX_SIZE_MM}
_SIZES = {"type": "numbers", "unit": "mm", "low": 0.0, "open_low": True, "high": MAX_SIZE_MM, "required": True}

FRAME = Table(
    "The pallet's frame from three taught points (base frame).",
    {
        "origin": Key(**_POINT, doc="the pallet's corner"),
        "x_point": Key(**_POINT, doc="a point along the pallet's x edge"),
        "xy_point": Key(**_POINT, doc="a point in the pallet's plane on its +y side"),
    },
)
FAMILY = Table(
    "A generated pattern.",
    {
        "family": Key("string", "the pattern family", choices=FAMILIES, required=True),
        "mirror": Key("boolean", "mirrored: x -> L - x, angle -> -angle", default=False),
        "label_out": Key("boolean", "the boxes' labels turned outwards", default=False),
    },
)
SLIP_SHEET = Table(
    "A slip sheet between layers.",
    {
        "every": Key("integer", "on top of every n-th layer", low=1, high=MAX_LAYERS, required=True),
        "thickness": Key(
            "number", "the sheet's thickness", unit="mm", low=0.0, open_low=True, high=50.0, required=True
        ),
        "pick": Key(
            "pose",
            "where a sheet is picked from its stack or dispenser, base frame, in the cell's pose format",
            count=(6, 7),
            required=True,
            low=-TAUGHT_RANGE_MM,
            high=TAUGHT_RANGE_MM,
        ),
        "lift": Key(
            "number",
            "the sheet comes off its stack straight along the base's z",
            unit="mm",
            low=0.0,
            open_low=True,
            high=2000.0,
            default=100.0,
        ),
    },
)


def _pallet_facts(target: str) -> dict:
    return get_target(target).kind_tables.get("pallet", {})


def _per_target(doc: str, targets: tuple[str, ...], value) -> Key:
    """A value for each of these controllers (value(target): its Key)."""
    return Key("map", doc, names=targets, per_name={t: value(t) for t in targets}, controllers=", ".join(targets))


def _per_cell_target(doc: str, targets: tuple[str, ...], value) -> Key:
    """A value for each of the cell's targets among these controllers (value(target): its Key), none for the others."""
    return replace(_per_target(doc, targets, value), per_target=True)


def _register(target: str) -> Key:
    facts = _pallet_facts(target)
    return Key(
        "integer",
        f"the first of the two {target} registers (the layer's; the box's is the next)",
        low=facts["registers"],
        high=facts["registers_max"] - 1,
        controllers=target,
    )


_TASK_TARGETS = tuple(t for t in target_names() if _pallet_facts(t).get("task"))
_REGISTER_TARGETS = tuple(t for t in target_names() if "registers" in _pallet_facts(t))
IO = Table(
    "The cell's inputs the program waits for (each at most timeout_s, then a stop with a message), the PLC's counter "
    "reset with its handshake output (done) and program selection, the PLC registers of the counters.",
    {
        "part_present": signals("stacking: on when a box lies at the pick place Q (required when stacking)"),
        "place_clear": signals("unstacking: on when Q is clear for a box (required when unstacking)"),
        "pallet_present": signals("on when the pallet stands in place", required=True),
        "sheet_ready": signals("on when a slip sheet is ready at its stack (required with slip_sheet)"),
        "reset": signals(
            "on when the PLC asks for a swapped pallet's counters to start again (honoured on a full or empty one, "
            "once the PLC drops it in answer to the done output going off)"
        ),
        "done": signals(
            "an output: on while the pallet is full (stacking) or empty (unstacking); the program turns it off to "
            "acknowledge the reset (required with reset)"
        ),
        "q_zone": signals(
            "an output: on while the arm is in the pick place's zone, from its stop above Q before it goes down until "
            "its stop above Q after it came back up (the PLC indexes no box into Q while it is on; requires q_done)"
        ),
        "q_done": signals(
            "an output: stacking, pick done (on once a box was taken from Q and the arm is out of the zone); "
            "unstacking, place done (on once a box was put down at Q and the arm is out); off as the arm goes into "
            "the zone again (requires q_zone)"
        ),
        "sheet_zone": signals(
            "an output: on while the arm is in the slip-sheet dispenser's zone, as q_zone at Q (with slip_sheet; "
            "requires sheet_taken)"
        ),
        "sheet_taken": signals(
            "an output: on once a sheet was taken from the dispenser and the arm is out of its zone; off as the arm "
            "goes into it again (requires sheet_zone)"
        ),
        "select": _per_cell_target(
            "the input that selects this pallet's program where the pallets share one task (required with several "
            "pallets)",
            _TASK_TARGETS,
            lambda t: signal_key(t, f"the select input on {t}"),
        ),
        "registers": _per_target(
            "the first PLC register of the counters (default: two per pallet from the first)",
            _REGISTER_TARGETS,
            _register,
        ),
        "timeout_s": Key("number", "how long each wait lasts", unit="s", low=0.5, high=600.0, default=TIMEOUT_S),
    },
)
PATTERN = Key(
    "either",
    "a pattern: a list of boxes [x, y, angle] (mm, deg, pallet frame) or a generated family",
    alternatives=(
        Key(
            "list",
            "boxes [x, y, angle]",
            non_empty=True,
            values=Key("numbers", "a box: x, y (mm), angle (deg)", count=3, low=-MAX_SIZE_MM, high=MAX_SIZE_MM),
        ),
        Key("table", FAMILY.doc, table=FAMILY),
    ),
)
PALLET = Table(
    "A pallet to stack boxes on (or take them off): its frame, box, layers and patterns.",
    {
        "name": Key("string", "the pallet's name (its program's)", required=True, non_empty=True),
        "frame": Key("table", FRAME.doc, table=FRAME, required=True, flatten=""),
        "size": Key(**_SIZES, count=2, doc="the pallet's length along its x and width along its y"),
        "box": Key(**_SIZES, count=3, doc="the box: length (its x at angle 0), width, height"),
        "layers": Key("integer", "layers in the stack", low=1, high=MAX_LAYERS, required=True),
        "cycle": Key(
            "list",
            "the patterns of the layers, repeated",
            required=True,
            non_empty=True,
            values=Key("string", "a pattern's name"),
        ),
        "angle_sense": Key(
            "string", "how the pattern angles turn, seen from above", choices=("cw", "ccw"), default="ccw"
        ),
        "tool_orientation": Key(
            "numbers",
            "a, b, c of a target at box angle 0, pallet frame",
            unit="deg",
            count=3,
            low=-360.0,
            high=360.0,
            default=(0.0, 0.0, 180.0),
        ),
        "entry_dz": Key(
            "number",
            "the entry above a box's target",
            unit="mm",
            low=0.0,
            open_low=True,
            high=MAX_SIZE_MM,
            required=True,
        ),
        "approach": Key(**_OFFSET, required=True, doc="the approach offset from the target (z above it, > 0)"),
        "retreat": Key(**_OFFSET, doc="the retreat offset from the target (default: the approach)"),
        "pick": Key(
            "pose",
            "the pick pose Q, base frame, in the cell's pose format",
            count=(6, 7),
            required=True,
            low=-TAUGHT_RANGE_MM,
            high=TAUGHT_RANGE_MM,
        ),
        "pick_lift": Key(
            "number",
            "the box comes off (goes onto) Q straight along the base's z",
            unit="mm",
            low=0.0,
            open_low=True,
            high=2000.0,
            default=100.0,
        ),
        "patterns": Key("map", "the layer patterns by name", required=True, non_empty=True, values=PATTERN),
        "overhang_mm": Key(
            "number", "how far a box may reach beyond the pallet's edge", unit="mm", low=0.0, high=200.0, default=0.0
        ),
        "transit_clearance_mm": Key(
            "number",
            "the carried box's bottom this far above the stack's top where it travels over the pallet (the entry at "
            "least the box's height above the target)",
            unit="mm",
            low=0.0,
            high=MAX_SIZE_MM,
            default=10.0,
        ),
        "support_min": Key(
            "number", "warn when less of a box's bottom rests on the layer below", low=0.0, high=1.0, default=0.6
        ),
        "slip_sheet": Key("table", SLIP_SHEET.doc, table=SLIP_SHEET, flatten="slip_"),
        "mode": Key(
            "string",
            "stack: place the boxes from Q; unstack: take them off, top layer first, to Q",
            choices=("stack", "unstack"),
            default="stack",
        ),
        "approach_auto": Key(
            "boolean", "approach and retreat from the side away from the layer's earlier boxes", default=False
        ),
        "io": Key(
            "table",
            "the inputs the program waits for (pallet_present, and part_present when stacking or place_clear when "
            "unstacking), per target",
            table=IO,
            required=True,
        ),
        "box_mass_kg": Key(
            "number",
            "the carried box's mass (its payload; 0: the tool's alone)",
            unit="kg",
            low=0.0,
            high=2000.0,
            default=0.0,
        ),
        "box_cog_mm": Key(
            "numbers",
            "the box's centre of gravity in the TCP frame (default: half its height along the tool's z)",
            unit="mm",
            count=3,
            low=-MAX_SIZE_MM,
            high=MAX_SIZE_MM,
        ),
        "config": Key(
            "map",
            "per target with an arm: the configuration above Q (the target's own form or { joints = [...] }), every "
            "joint move of the cycle worked in its branch (default: the controller's own from the home, else one "
            "chosen to clear the cell)",
            names=robot.arm_targets(),
            values=Key(
                "either",
                "a configuration",
                alternatives=(
                    Key(
                        "list",
                        "configuration data [cf1, cf4, cf6, cfx] or joints (deg), as the target's form",
                        values=Key("number", "one"),
                    ),
                    Key("map", "{ s = status, t = turn } or { joints = [...] } (deg), as the target's form"),
                ),
            ),
        ),
        "base_data": Key(
            "integer",
            "the controller's numbered base the program reads the pallet frame from (measured there with the base "
            "wizard; the frame's points give its nominal value and what the measured one may differ by)",
            low=1,
            controllers="those with numbered base data (BASE_DATA[n])",
        ),
        "zone_mm": Key(
            "number",
            "blending where the arm passes a pose (default: [cell.motion] zone_mm)",
            unit="mm",
            low=0.0,
            high=200.0,
        ),
    },
)
KEYS = KindKeys(tables={"pallet": Key("tables", PALLET.doc, table=PALLET)}, reads=("io",))
