"""The cell file's own tables ([cell], the tables every kind shares) as data, with the kinds' parts: what the loader
reads."""

from __future__ import annotations

import json
from dataclasses import replace
from functools import cache

from codegen.controllers import target_names
from codegen.model import io, motion, robot, vision
from codegen.model.schema import JSON_SCHEMA_DRAFT, Key, Table, json_of_table, markdown
from codegen.protocol import kinds

CELL_POSE_FORMATS = ("xyzabc", "ur", "abb")
OWN_KEYS = ("name", "targets", "pose_format")  # [cell]'s own values (its other keys are tables)


def _readers(table: str) -> tuple[str, ...]:
    """The kinds (as the cell file's reference lists them) whose programs read a shared [cell.<table>]."""
    return tuple(n for k in kinds().values() if k.cell_file and table in k.cell_file.reads for n in k.listed_names())


def _listed(kind, keys: dict[str, Key]) -> dict[str, Key]:
    """A kind's tables, each listed under the kind (or under what the key names itself)."""
    return {name: replace(key, kinds=key.kinds or kind.listed_names()) for name, key in keys.items()}


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
        "robot": Key(
            "table", robot.robot_table().doc, table=robot.robot_table(), controllers=", ".join(robot.arm_targets())
        ),
        "tool": Key("table", robot.TOOL.doc, table=robot.tool_table()),
        "vision": Key(
            "table", vision.TABLE.doc, table=replace(vision.TABLE, kinds=_readers("vision")), kinds=_readers("vision")
        ),
        "motion": Key("table", motion.TABLE.doc, table=motion.TABLE),
        "io": Key(
            "table",
            io.io_table().doc,
            table=io.io_table(),
            kinds=_readers("io"),
            controllers=", ".join(io.signal_targets()),
        ),
    }
    for kind in kinds().values():
        if kind.cell_file is not None:
            own.update(_listed(kind, kind.cell_file.cell_tables))
    return Table("The cell: its name, controllers, pose format and the tables every kind shares.", own)


def own_table() -> Table:
    """[cell]'s own values, as the loader reads them (the tables in it are read by their own sections)."""
    definition = cell_table()
    return Table(definition.doc, {name: definition[name] for name in OWN_KEYS})


@cache
def file_table() -> Table:
    """The whole cell file: [cell] and the kinds' top-level tables."""
    top = {"cell": Key("table", cell_table().doc, table=cell_table(), required=True)}
    for kind in kinds().values():
        if kind.cell_file is not None:
            top.update(_listed(kind, kind.cell_file.tables))
    return Table("A codegen cell file.", top)


def json_schema() -> dict:
    """The cell file's JSON Schema (draft 2020-12): a cell has one kind's tables at least, and each kind adds the
    rules between its tables the definition states (ProgramKind.json_schema)."""
    out = {"$schema": JSON_SCHEMA_DRAFT, "title": "codegen cell file", **json_of_table(file_table())}
    out["anyOf"] = [{"required": [name]} for name in out["properties"] if name != "cell"]
    for kind in kinds().values():
        kind.json_schema(out)
    return out


def schema_text() -> str:
    """The JSON Schema as shipped (codegen/examples/cell.schema.json): in definition order, two-space indent."""
    return json.dumps(json_schema(), indent=2, sort_keys=False) + "\n"


def reference_text() -> str:
    """The cell-file reference page (docs/cell-file-reference.md)."""
    return markdown(file_table(), "Cell file reference")
