"""The cell's solids from [cell.world]: the floor, the keep-out boxes and cylinders, the clearance every move keeps."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from codegen.guard import TAUGHT_RANGE_MM
from codegen.model.loader import Loader
from codegen.model.schema import Key, Table

# the clearance every planned move keeps (docs/clearance.md says why 20 mm); the sampling of a move guarantees
# contact is found at any clearance, and below 1 mm the arm's estimated shapes say nothing
CLEARANCE_DEFAULT_MM = 20.0
SIZE_MAX_MM = 2 * TAUGHT_RANGE_MM  # a solid larger than the taught range is no cell's
_SIZE = {"unit": "mm", "low": 0.0, "open_low": True, "high": SIZE_MAX_MM}
SHAPES = ("box", "cylinder")  # the keys that give a solid's shape: exactly one of them

SOLID = Table(
    "A keep-out solid: a box or a cylinder, centred on its pose (world frame: the robot's base frame).",
    {
        "box": Key("numbers", "a box of this size x, y, z along the pose's axes", count=3, **_SIZE),
        "cylinder": Key("numbers", "a cylinder of this radius and length along the pose's z axis", count=2, **_SIZE),
        "pose": Key(
            "pose",
            "the solid's centre and axes in the robot's base frame, in the cell's pose format",
            count=(6, 7),
            low=-TAUGHT_RANGE_MM,
            high=TAUGHT_RANGE_MM,
            required=True,
        ),
    },
)

SOLIDS = Key(
    "map",
    "keep-out solids by name: { box = [x, y, z], pose = [...] } or { cylinder = [radius, length], pose = [...] }",
    values=Key("table", SOLID.doc, table=SOLID),
)

TABLE = Table(
    "The cell as solid objects (optional): the floor or the robot's mounting plane, the keep-out solids (machines, "
    "fences, tables) and the clearance every planned move keeps from them. Each program kind adds its own solids "
    "(what its programs work at).",
    {
        "floor_z_mm": Key(
            "number",
            "everything below this height of the robot's base frame is solid: the floor or the mounting plane (the "
            "arm's base link stands on it and is not checked against it)",
            unit="mm",
            low=-TAUGHT_RANGE_MM,
            high=TAUGHT_RANGE_MM,
            default=0.0,
        ),
        "clearance_mm": Key(
            "number",
            "the least distance every planned move keeps between the arm, its tool and the part it carries and every "
            "solid (and between the arm's own links)",
            unit="mm",
            low=1.0,
            high=1000.0,
            default=CLEARANCE_DEFAULT_MM,
        ),
        "solids": SOLIDS,
    },
)

PART = Table(
    "The part the gripper carries: a box hanging from the TCP along the tool's z (gripped at the middle of its top "
    "face).",
    {"size_mm": Key("numbers", "the part's size x, y, z in the TCP's axes", count=3, required=True, **_SIZE)},
)


@dataclass(frozen=True)
class SolidSpec:
    """A declared solid: "box" (size x, y, z) or "cylinder" (radius, length), centred on solid2base (mm)."""

    shape: str
    size: tuple[float, ...]
    solid2base: np.ndarray = field(compare=False)


@dataclass(frozen=True)
class WorldSettings:
    """[cell.world]: the floor's height, the clearance and the declared solids by name."""

    floor_z_mm: float = TABLE.default("floor_z_mm")
    clearance_mm: float = TABLE.default("clearance_mm")
    solids: dict = field(default_factory=dict, compare=False)  # name -> SolidSpec


@dataclass(frozen=True)
class PartShape:
    """A carried part: a box of size_mm in the TCP's axes, hanging from the TCP."""

    size_mm: tuple[float, float, float]


def parse_settings(ctx, cell_table: dict, pose_format: str) -> WorldSettings:
    """[cell.world] of a cell file (optional), read by its declaration (TABLE); errors name the key."""
    if "world" not in cell_table:
        return WorldSettings()
    values = Loader(ctx, pose_format).table(TABLE, cell_table["world"], "cell.world")
    solids = specs(ctx, values["solids"], "cell.world.solids")
    return WorldSettings(values["floor_z_mm"], values["clearance_mm"], solids)


def specs(ctx, read: dict | None, path: str) -> dict[str, SolidSpec]:
    """Solids read by SOLIDS' declaration (name -> its table's values) as SolidSpecs: one shape each."""
    out = {}
    for name, raw in (read or {}).items():
        where = f"{path}.{name}"
        if not name.strip():
            ctx.fail(where, "a solid's name must not be empty")
        given = [key for key in SHAPES if raw[key] is not None]
        if len(given) != 1:
            said = "both" if given else "neither"
            ctx.fail(where, f"a solid is a box (box = [x, y, z]) or a cylinder (cylinder = [r, length]); got {said}")
        out[name] = SolidSpec(given[0], tuple(raw[given[0]]), raw["pose"].matrix())
    return out


def parse_solids(ctx, raw, path: str, pose_format: str) -> dict[str, SolidSpec]:
    """A table of named solids (SOLIDS) outside [cell.world] (a station's), {} where not given."""
    if raw is None:
        return {}
    return specs(ctx, Loader(ctx, pose_format).value(SOLIDS, raw, path), path)


def parse_part(ctx, raw, path: str) -> PartShape | None:
    """A part table ({ size_mm = [x, y, z] }) read by its declaration (PART); None where not given."""
    if raw is None:
        return None
    return PartShape(Loader(ctx).table(PART, raw, path)["size_mm"])
