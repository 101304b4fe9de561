"""The pallet kind's part of the cell file: the [[pallet]] tables."""

from __future__ import annotations

from codegen.guard import TAUGHT_RANGE_MM
from codegen.model.schema import Key, KindKeys, Table

MAX_LAYERS = 200
MAX_SIZE_MM = 5000.0
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
        "frame": Key("table", FRAME.doc, table=FRAME, required=True),
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
        "support_min": Key(
            "number", "warn when less of a box's bottom rests on the layer below", low=0.0, high=1.0, default=0.6
        ),
        "slip_sheet": Key("table", SLIP_SHEET.doc, table=SLIP_SHEET),
        "mode": Key(
            "string",
            "stack: place the boxes from Q; unstack: take them off, top layer first, to Q",
            choices=("stack", "unstack"),
            default="stack",
        ),
        "approach_auto": Key(
            "boolean", "approach and retreat from the side away from the layer's earlier boxes", default=False
        ),
    },
)
KEYS = KindKeys(tables={"pallet": Key("tables", PALLET.doc, table=PALLET)})
