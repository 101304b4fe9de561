"""The station kind's part of the cell file: [[station]] (each mode's keys beside the common ones), [cell.camera],
[cell.limits] and the modes' [cell.<name>] tables."""

from __future__ import annotations

from dataclasses import replace
from functools import cache

from codegen.guard import READING_RANGE_MM, TAUGHT_RANGE_MM
from codegen.kinds.station.mode import modes
from codegen.model import robot, world
from codegen.model.schema import Key, KindKeys, Table

NAME = "station"  # the kind's name: its [[station]] tables, its section of the cell
GRIP, RELEASE = "grip", "release"  # what the gripper does at a station's pose ([station.gripper])
STATION_ID_MAX = 32767  # the largest 16-bit signed integer, which every target reads without loss
VISION_TABLES = ("camera", "limits")  # [cell] tables a cell with [[station]] needs (a standalone kind's does not)
PART_MASS_MAX_KG = 2000.0  # above every catalogue arm's payload: the arm's own payload refuses less (check_carried)

POSE = Key(
    "pose",
    "a taught pose in the cell's pose format: 6 numbers (xyzabc, ur) or 7 (abb)",
    count=(6, 7),
    low=-TAUGHT_RANGE_MM,
    high=TAUGHT_RANGE_MM,
)


# [station.part]: the shape the sweep checks (model.world.PART) and what a cell engineer knows of the part besides:
# its mass (weighed, or from the drawing) and, for a part whose mass is not spread evenly (a shaft with a flange),
# where its centre of gravity lies from the TCP; the load from the confirmed grip to the confirmed release
PART = world.PART.merged(
    {
        "mass_kg": Key(
            "number",
            "the part's mass: the load the gripper carries from the confirmed grip to the confirmed release (the "
            "tool's and the part's as one; 0: the tool's alone)",
            unit="kg",
            low=0.0,
            high=PART_MASS_MAX_KG,
            default=0.0,
        ),
        "cog_mm": Key(
            "numbers",
            "the part's centre of gravity in the TCP frame (default: its box's centre, half its height along the "
            "tool's z)",
            unit="mm",
            count=3,
            low=-world.SIZE_MAX_MM,
            high=world.SIZE_MAX_MM,
        ),
    }
)


def default_mode() -> str:
    """The cell file's contract: a station without `mode` has the first mode (in `order`)."""
    return next(iter(modes()))


def mode_names() -> tuple[str, ...]:
    return tuple(modes())


@cache
def camera() -> Table:
    users = tuple(name for name, mode in modes().items() if mode.reads_pixels)
    return Table(
        "The camera that reads the marks (required with [[station]]).",
        {
            "angle_sign": Key(
                "integer",
                "the sign the camera's angles turn with: -1 when its image is mirrored (they turn against the frame's)",
                choices=(1, -1),
                required=True,
            ),
            "handeye": Key(
                "table",
                f"the camera's hand-eye map ({', '.join(users)} stations read pixels)",
                table=Table(
                    "pixel -> mm: [[a, b, tx], [c, d, ty]] (`codegen calibrate handeye` writes it).",
                    {
                        "pixel_to_mm": Key(
                            "list",
                            "2 rows of 3 numbers [[a, b, tx], [c, d, ty]]",
                            required=True,
                            count=2,
                            values=Key(
                                "numbers",
                                "a row [a, b, tx] or [c, d, ty]",
                                count=3,
                                low=-READING_RANGE_MM,
                                high=READING_RANGE_MM,
                            ),
                        )
                    },
                ),
                kinds=users,
            ),
        },
        kinds=mode_names(),
    )


@cache
def limits() -> Table:
    return Table(
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
        kinds=mode_names(),
    )


@cache
def _common() -> Table:
    """The keys every station has, whatever its mode."""
    names = mode_names()
    own = {
        "id": Key(
            "integer", "the station's id (the barcode the vision PC reads)", low=1, high=STATION_ID_MAX, required=True
        ),
        "name": Key("string", "the station's name", required=True, non_empty=True),
        "mode": Key("string", "the station's program kind", choices=names, default=default_mode()),
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
        "gripper": Key(
            "map",
            "pose name -> what the gripper ([cell.io]) does once the arm stands at that pose: grip (take a part) or "
            "release (put it down); a pose not named: neither. Without it the station moves and the gripper stays "
            "as it is",
            values=Key("string", "what the gripper does there", choices=(GRIP, RELEASE)),
        ),
        "part": Key("table", PART.doc + " (the part the station's grip takes)", table=PART),
        "solids": replace(
            world.SOLIDS,
            doc="the station's own keep-out solids (the machine it serves, with its door's opening left free), in the "
            "base frame at calibration; they move with the station's reading, as its poses do: " + world.SOLIDS.doc,
        ),
    }
    return Table("A station the program serves: its id, poses and its kind's keys.", own, kinds=names)


@cache
def station_table(mode: str | None = None) -> Table:
    """[[station]]: the keys every station has, and each mode's own (required by its mode only); of one mode (the
    loader's): its own keys as the mode declares them, no other mode's."""
    if mode is not None:
        return _common().merged(modes()[mode].station_keys())
    return _common().merged(
        {
            key: replace(value, required=False, kinds=(name,))
            for name, mode in modes().items()
            for key, value in mode.station_keys().items()
        }
    )


@cache
def kind_keys() -> KindKeys:
    """The kind's part of the cell file (its modes' keys with it)."""
    stations = station_table()
    return KindKeys(
        reads=("io", "vision"),
        tables={NAME: Key("tables", stations.doc, table=stations, kinds=stations.kinds)},
        cell_tables={
            "camera": Key("table", camera().doc, table=camera(), kinds=camera().kinds),
            "limits": Key("table", limits().doc, table=limits(), kinds=limits().kinds),
            **{
                name: replace(key, kinds=(m,))
                for m, mode in modes().items()
                if mode.cell_file is not None
                for name, key in mode.cell_file.cell_tables.items()
            },
        },
    )
