"""The cell file's own tables ([cell], [cell.*], [[station]]) as data, with the kinds' parts: what the loader reads."""

from __future__ import annotations

import json
from dataclasses import replace
from functools import cache

from codegen.controllers import target_names
from codegen.guard import READING_RANGE_MM, TAUGHT_RANGE_MM
from codegen.model import io, motion, robot, vision
from codegen.model.schema import JSON_SCHEMA_DRAFT, Key, Table, json_of_table, markdown
from codegen.protocol import kinds, station_kinds

CELL_POSE_FORMATS = ("xyzabc", "ur", "abb")
DEFAULT_MODE = "point"  # the cell file's contract: a station without `mode` is a point station
STATION_ID_MAX = 32767  # the largest 16-bit signed integer, which every target reads without loss
VISION_TABLES = ("camera", "limits")  # [cell] tables a cell with [[station]] needs (a standalone kind's does not)

CAMERA = Table(
    "The camera that reads the marks (required with [[station]]).",
    {
        "angle_sign": Key(
            "integer",
            "-1 when the camera's image is mirrored (its angles turn against the frame's)",
            choices=(1, -1),
            required=True,
        ),
        "handeye": Key(
            "table",
            "the camera's hand-eye map (frame stations read pixels)",
            table=Table(
                "pixel -> mm: [[a, b, tx], [c, d, ty]] (`codegen calibrate handeye` writes it).",
                {
                    "pixel_to_mm": Key(
                        "list",
                        "2 rows of 3 numbers [[a, b, tx], [c, d, ty]]",
                        required=True,
                        count=2,
                        values=Key("numbers", "a row", count=3, low=-READING_RANGE_MM, high=READING_RANGE_MM),
                    )
                },
            ),
            kinds=("frame",),
        ),
    },
    kinds=("point", "frame"),
)
LIMITS = Table(
    "How far a reading may move a station before the program refuses it (required with [[station]]).",
    {
        "max_shift_mm": Key(
            "number",
            "the largest shift of the mark",
            unit="mm",
            low=0.0,
            open_low=True,
            high=READING_RANGE_MM,
            required=True,
        ),
        "max_rotation_deg": Key(
            "number",
            "the largest rotation of the mark",
            unit="deg",
            low=0.0,
            open_low=True,
            high=180.0,
            open_high=True,
            required=True,
        ),
    },
    kinds=("point", "frame"),
)
POSE = Key(
    "pose",
    "a taught pose in the cell's pose format: 6 numbers (xyzabc, ur) or 7 (abb)",
    count=(6, 7),
    low=-TAUGHT_RANGE_MM,
    high=TAUGHT_RANGE_MM,
)


@cache
def cell_table() -> Table:
    """[cell] with its tables and the kinds' [cell.<name>] tables."""
    own = {
        "name": Key("string", "the cell's name (the programs' folder)", required=True, non_empty=True),
        "targets": Key(
            "list",
            "the controllers to write programs for",
            required=True,
            non_empty=True,
            unique=True,
            values=Key("string", "a controller", choices=target_names()),
        ),
        "pose_format": Key("string", "how a taught pose is written", choices=CELL_POSE_FORMATS, default="xyzabc"),
        "camera": Key("table", CAMERA.doc, table=CAMERA, kinds=CAMERA.kinds),
        "limits": Key("table", LIMITS.doc, table=LIMITS, kinds=LIMITS.kinds),
        "robot": Key(
            "table", robot.robot_table().doc, table=robot.robot_table(), controllers=", ".join(robot.arm_targets())
        ),
        "tool": Key("table", robot.TOOL.doc, table=robot.tool_table()),
        "vision": Key("table", vision.TABLE.doc, table=vision.TABLE, kinds=vision.TABLE.kinds),
        "motion": Key("table", motion.TABLE.doc, table=motion.TABLE),
        "io": Key(
            "table",
            io.io_table().doc,
            table=io.io_table(),
            kinds=tuple(k.name for k in kinds().values() if k.cell_file and "io" in k.cell_file.reads),
            controllers=", ".join(io.signal_targets()),
        ),
    }
    for kind in kinds().values():
        if kind.cell_file is not None:
            own.update({name: replace(key, kinds=(kind.name,)) for name, key in kind.cell_file.cell_tables.items()})
    return Table("The cell: its name, controllers, pose format and the tables every kind shares.", own)


@cache
def station_table() -> Table:
    """[[station]]: the keys every station has, and each station kind's own."""
    modes = tuple(station_kinds())
    own = {
        "id": Key(
            "integer", "the station's id (the barcode the vision PC reads)", low=1, high=STATION_ID_MAX, required=True
        ),
        "name": Key("string", "the station's name", required=True, non_empty=True),
        "mode": Key("string", "the station's program kind", choices=modes, default=DEFAULT_MODE),
        "poses": Key(
            "map",
            "the taught poses by name, in visiting order (the last is the work pose)",
            required=True,
            non_empty=True,
            values=POSE,
        ),
        "config": Key(
            "map",
            "per target with an arm: pose name -> its configuration (the target's own form or { joints = [...] })",
            names=robot.arm_targets(),
            values=Key("map", "pose -> configuration"),
        ),
    }
    return Table("A station the program serves: its id, poses and its kind's keys.", own, kinds=modes)


def station_kind_keys() -> dict[str, dict[str, Key]]:
    """Each station kind's own [[station]] keys."""
    return {name: kind.cell_file.station_keys for name, kind in station_kinds().items() if kind.cell_file}


@cache
def file_table() -> Table:
    """The whole cell file: [cell], [[station]] and the kinds' top-level tables."""
    # each kind's keys, required by its mode only (json_schema's rules)
    own = {
        k: replace(v, required=False, kinds=(m,)) for m, keys in station_kind_keys().items() for k, v in keys.items()
    }
    stations = station_table().merged(own)
    top = {
        "cell": Key("table", cell_table().doc, table=cell_table(), required=True),
        "station": Key("tables", stations.doc, table=stations, kinds=stations.kinds),
    }
    for kind in kinds().values():
        if kind.cell_file is not None:
            top.update({name: replace(key, kinds=(kind.name,)) for name, key in kind.cell_file.tables.items()})
    return Table("A codegen cell file.", top)


def json_schema() -> dict:
    """The cell file's JSON Schema (draft 2020-12), with the rules between tables the definition states: a
    station's kind's keys, and camera and limits with [[station]]."""
    out = {"$schema": JSON_SCHEMA_DRAFT, "title": "codegen cell file", **json_of_table(file_table())}
    station = out["properties"]["station"]["items"]
    kind_keys = station_kind_keys()
    rules = []
    for mode, keys in kind_keys.items():
        others = {k: False for m, ks in kind_keys.items() if m != mode for k in ks if k not in keys}
        condition: dict = {"properties": {"mode": {"enum": [mode]}}}
        if mode != DEFAULT_MODE:
            condition["required"] = ["mode"]
        then: dict = {"properties": others}
        required = [k for k, key in keys.items() if key.required]
        if required:
            then["required"] = required
        rules.append({"if": condition, "then": then})
    station["allOf"] = rules
    standalone = [name for name in out["properties"] if name not in ("cell", "station")]
    out["anyOf"] = [{"required": ["station"]}, *({"required": [name]} for name in standalone)]
    out["allOf"] = [
        {
            "if": {"required": ["station"]},
            "then": {"properties": {"cell": {"required": list(VISION_TABLES)}}},
        }
    ]
    return out


def schema_text() -> str:
    """The JSON Schema as shipped (codegen/examples/cell.schema.json): in definition order, two-space indent."""
    return json.dumps(json_schema(), indent=2, sort_keys=False) + "\n"


def reference_text() -> str:
    """The cell-file reference page (docs/cell-file-reference.md)."""
    return markdown(file_table(), "Cell file reference")
