"""The cell file's own tables ([cell], the tables every kind shares) as data, with the kinds' parts: what the loader
reads."""

from __future__ import annotations

import json
from dataclasses import replace
from functools import cache

from codegen.controllers import target_names
from codegen.model import io, motion, robot, vision, world
from codegen.model.schema import JSON_SCHEMA_DRAFT, REFERENCE_NOTE, Key, Table, json_of_table, markdown
from codegen.protocol import Kinds, installed_kinds

CELL_POSE_FORMATS = ("xyzabc", "ur", "abb")
OWN_KEYS = ("name", "targets", "pose_format")  # [cell]'s own values (its other keys are tables)


def _readers(kinds: Kinds, table: str) -> tuple[str, ...]:
    """The kinds (as the cell file's reference lists them) whose programs read a shared [cell.<table>]."""
    sections = [k.section for k in kinds.values()]
    return tuple(n for s in sections if s.keys and table in s.keys.reads for n in s.listed_names())


def _listed(section, keys: dict[str, Key]) -> dict[str, Key]:
    """A kind's tables, each listed under the kind (or under what the key names itself)."""
    return {name: replace(key, kinds=key.kinds or section.listed_names()) for name, key in keys.items()}


@cache
def cell_table(kinds: Kinds) -> Table:
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
            "table",
            vision.TABLE.doc,
            table=replace(vision.TABLE, kinds=_readers(kinds, "vision")),
            kinds=_readers(kinds, "vision"),
        ),
        "motion": Key("table", motion.TABLE.doc, table=motion.TABLE),
        "world": Key("table", world.TABLE.doc, table=world.TABLE),
        "io": Key(
            "table",
            io.io_table().doc,
            table=io.io_table(),
            kinds=_readers(kinds, "io"),
            controllers=", ".join(io.signal_targets()),
        ),
    }
    for section in (kind.section for kind in kinds.values()):
        if section.keys is not None:
            own.update(_listed(section, section.keys.cell_tables))
    return Table("The cell: its name, controllers, pose format and the tables every kind shares.", own)


def own_table(kinds: Kinds) -> Table:
    """[cell]'s own values, as the loader reads them (the tables in it are read by their own sections)."""
    definition = cell_table(kinds)
    return Table(definition.doc, {name: definition[name] for name in OWN_KEYS})


@cache
def file_table(kinds: Kinds) -> Table:
    """The whole cell file: [cell] and the kinds' top-level tables."""
    top = {"cell": Key("table", cell_table(kinds).doc, table=cell_table(kinds), required=True)}
    for section in (kind.section for kind in kinds.values()):
        if section.keys is not None:
            top.update(_listed(section, section.keys.tables))
    return Table("A codegen cell file.", top)


def json_schema(kinds: Kinds | None = None) -> dict:
    """The cell file's JSON Schema (draft 2020-12) of the kinds (default: the installed ones): a cell has one kind's
    tables at least, and each kind adds the rules between its tables the definition states (Section.json_schema)."""
    kinds = installed_kinds() if kinds is None else kinds
    out = {"$schema": JSON_SCHEMA_DRAFT, "title": SCHEMA_TITLE, **json_of_table(file_table(kinds))}
    out["anyOf"] = [{"required": [name]} for name in out["properties"] if name != "cell"]
    for kind in kinds.values():
        kind.section.json_schema(out)
    return out


SCHEMA_TITLE = "codegen cell file"
# `codegen schema --out` replaces only a file with one of these in its first lines (the schema's or the page's)
SCHEMA_MARKS = (json.dumps({"title": SCHEMA_TITLE})[1:-1].encode(), REFERENCE_NOTE.encode())


def schema_text(kinds: Kinds | None = None) -> str:
    """The JSON Schema as shipped (codegen/examples/cell.schema.json): in definition order, two-space indent."""
    return json.dumps(json_schema(kinds), indent=2, sort_keys=False) + "\n"


def reference_text(kinds: Kinds | None = None) -> str:
    """The cell-file reference page (docs/cell-file-reference.md) of the kinds (default: the installed ones)."""
    return markdown(file_table(installed_kinds() if kinds is None else kinds), "Cell file reference")
