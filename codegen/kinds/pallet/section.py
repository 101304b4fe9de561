"""The [[pallet]] tables of a cell file, validated (file, key path; exit 2 through CellError)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from codegen.controllers import get_target
from codegen.kinds.pallet.interlocks import PalletIO, check_one_job_each, check_pallets_io, parse_io
from codegen.kinds.pallet.keys import FAMILIES, MAX_LAYERS, PALLET
from codegen.model.cell import CellValidator
from codegen.model.loader import Loader, build
from codegen.model.robot import parse_cycle_config
from codegen.model.validate import metres_text, read_as_metres
from codegen.poses import rotmat_from_zyx_deg

# The most boxes a stack (every layer), a pattern or the patterns together may hold. The programs hold every
# box of the cycle's patterns in tables (7 to 9 numbers a box) and count boxes in a layer and layers; their
# counters would hold far more (each controller's integers: targets/<t>.toml), and no documented limit of the
# tables' length was found for any of the controllers. What binds is codegen's own work: verify runs the whole
# stack in the interpreter within its default step limit (200,000 steps; a box takes 60 to 85 of them on the four
# targets, its interlocks and slip sheets counted: about 2,400 boxes), and generate solves every move of the whole
# stack for each arm (8 moves a
# box, about 2 ms a box). 2,000 keeps both within that with room, and is far more than a pallet of cartons
# holds (a EUR pallet of 200 x 150 mm cartons: 32 a layer).
BOXES_MAX = 2000
PICK_LIFT_MM = PALLET.default("pick_lift")  # the default lift above Q


@dataclass(frozen=True)
class FamilySpec:
    """A generated pattern: its family, mirrored (x -> L - x, angle -> -angle), labels turned outwards."""

    family: str
    mirror: bool = False
    label_out: bool = False


@dataclass(frozen=True)
class Pallet:
    name: str
    origin: tuple[float, float, float]  # taught, base frame, mm
    x_point: tuple[float, float, float]
    xy_point: tuple[float, float, float]
    size: tuple[float, float]  # length along the pallet's x, width along its y, mm
    box: tuple[float, float, float]  # length (its x at angle 0), width, height, mm
    layers: int
    cycle: tuple[str, ...]
    angle_sense: str  # "cw" or "ccw": how the pattern angles turn, seen from above (+z)
    tool_orientation: tuple[float, float, float]  # a, b, c of a target at box angle 0, pallet frame
    entry_dz: float
    approach: tuple[float, float, float]
    retreat: tuple[float, float, float]
    pick: object  # pick pose Q (codegen.model.cell.TaughtPose, base frame) or None
    patterns: dict  # name -> tuple of (x, y, angle) or FamilySpec
    overhang_mm: float = 0.0  # how far a box may reach beyond the pallet's edge
    support_min: float = 0.6  # warn when less of a box's bottom rests on the layer below
    slip_every: int = 0  # a slip sheet on top of every n-th layer (0: none)
    slip_thickness: float = 0.0
    mode: str = "stack"  # "stack": place the boxes from Q; "unstack": take them off, top layer first, to Q
    approach_auto: bool = False  # approach and retreat from the side away from the layer's earlier boxes
    pick_lift: float = PICK_LIFT_MM  # the box comes off (goes onto) Q straight along the base's z, mm
    # the inputs the program waits for, the PLC's reset and selection (interlocks.py)
    io: PalletIO = field(default_factory=PalletIO)
    box_mass_kg: float = 0.0  # the carried box: its mass (0: the payload is the tool's alone)
    box_cog_mm: tuple[float, float, float] = (0.0, 0.0, 0.0)  # its centre of gravity in the TCP frame
    slip_pick: object = None  # where the slip sheets are picked (TaughtPose, base frame), or None: no sheets placed
    slip_lift: float = PICK_LIFT_MM  # the sheet comes off its stack straight along the base's z, mm
    zone_mm: float = 0.0  # blending where the arm passes a pose (0: it stops at each)
    transit_clearance_mm: float = 10.0  # the carried box's bottom above the stack's top where it travels over it
    # target -> the configuration above Q the cell names ([pallet.config], codegen.model.robot.PoseConfig): the
    # whole cycle is worked in its branch; a target without one: codegen/kinds/pallet/posture.py chooses
    config: dict = field(default_factory=dict)
    base_data: int | None = None  # the controller's numbered base holding the pallet frame (BASE_DATA[n]), or None


def parse_pallets(ctx: CellValidator, data: dict, cell) -> tuple[Pallet, ...]:
    """The [[pallet]] tables of a cell file (cell: as far as it is known: pose format, targets, motion)."""
    raw = data.get("pallet", [])
    if not isinstance(raw, list) or not all(isinstance(t, dict) for t in raw):
        ctx.fail("pallet", "expected [[pallet]] tables")
    loader = Loader(ctx, cell.pose_format, tuple(cell.targets))
    pallets = tuple(_pallet(ctx, loader, table, f"pallet[{i}]", cell) for i, table in enumerate(raw))
    names = [p.name for p in pallets]
    for i, name in enumerate(names):
        if name in names[:i]:
            ctx.fail(f"pallet[{i}].name", f"pallet {name!r} named twice")
    _check_bases(ctx, pallets, cell.targets)
    check_pallets_io(ctx, pallets, cell.targets)
    check_one_job_each(ctx, pallets, cell.io)
    return pallets


def _check_bases(ctx: CellValidator, pallets: tuple[Pallet, ...], targets) -> None:
    """Each numbered base within every cell target's bases, one pallet's each; a cell naming one has a target that
    keeps numbered bases."""
    limits = {t: get_target(t).program["base_data"]["max"] for t in targets if get_target(t).program.get("base_data")}
    for i, pallet in enumerate(pallets):
        if pallet.base_data is None:
            continue
        path = f"pallet[{i}].base_data"
        if not limits:
            ctx.fail(path, f"none of the cell's targets ({', '.join(targets)}) keeps numbered bases (BASE_DATA[n])")
        for target, top in limits.items():
            if pallet.base_data > top:
                ctx.fail(path, f"target {target} keeps bases 1..{top}, got {pallet.base_data}")
        shared = [p.name for p in pallets[:i] if p.base_data == pallet.base_data]
        if shared:
            ctx.fail(path, f"base {pallet.base_data} is pallet {shared[0]!r}'s already: each pallet has its own frame")


def _pallet(ctx: CellValidator, loader: Loader, table: dict, path: str, cell) -> Pallet:
    """One [[pallet]]: its keys as declared (keys.py), then the rules between them."""
    if "slip_sheet" in table and table.get("mode") == "unstack":  # before the sheet's keys: none of them applies
        ctx.fail(
            f"{path}.slip_sheet",
            "an unstacking program would grip the slip sheet on a layer with its box: codegen places slip "
            "sheets when stacking only",
        )
    values = loader.table(PALLET, table, path, readers={"config": lambda value, where: value})  # read with the arms
    _not_metres(ctx, values, path)
    patterns = _patterns(ctx, values["patterns"], f"{path}.patterns")
    cycle = values["cycle"]
    if len(cycle) > MAX_LAYERS:
        ctx.fail(f"{path}.cycle", f"{len(cycle)} patterns; at most {MAX_LAYERS}, the most layers a stack has")
    for i, entry in enumerate(cycle):
        if entry not in patterns:
            ctx.fail(f"{path}.cycle[{i}]", f"no pattern {entry!r}; the patterns: {', '.join(patterns)}")
    approach = values["approach"]
    retreat = values["retreat"] if values["retreat"] is not None else approach
    for key, offset in (("approach", approach), ("retreat", retreat)):
        if offset[2] <= 0:
            ctx.fail(f"{path}.{key}", "z must be above the target (> 0): the arm comes from above")
    down = float(rotmat_from_zyx_deg(*values["tool_orientation"])[2, 2])  # the tool's z along the pallet's z
    if down >= 0:
        ctx.fail(
            f"{path}.tool_orientation",
            f"the tool's z points {'up' if down > 0 else 'sideways'} (a, b, c = "
            f"{', '.join(f'{v:g}' for v in values['tool_orientation'])}): the TCP grips the box at its top, its z "
            "into the box, so it points down into the pallet (0, 0, 180 points it straight down)",
        )
    slip = values["slip_sheet"]
    if values["approach_auto"] and min(math.hypot(*approach[:2]), math.hypot(*retreat[:2])) < 1.0:
        ctx.fail(f"{path}.approach_auto", "turns the x-y part of approach and retreat: each needs one of 1 mm or more")
    io = parse_io(ctx, values["io"], f"{path}.io", cell.targets, values["mode"], slip is not None)
    box = values["box"]
    return build(
        Pallet,
        values,
        PALLET,
        cycle=tuple(cycle),
        patterns=patterns,
        retreat=retreat,
        io=io,
        # the TCP on the box's top, its z into the box: the box's centre
        box_cog_mm=values["box_cog_mm"] or (0.0, 0.0, box[2] / 2),
        zone_mm=values["zone_mm"] if values["zone_mm"] is not None else cell.motion.zone_mm,
        config=parse_cycle_config(ctx, values["config"], f"{path}.config", cell.robot),
    )


def _not_metres(ctx: CellValidator, values: dict, path: str) -> None:
    """The frame's points and Q (base frame, mm; Q in a "ur" cell metres as it should be), the pallet's and the box's
    sizes (mm in every cell) not written in metres."""
    pick = values["pick"]
    points = [(f"frame.{k}", values["frame"][k]) for k in ("origin", "x_point", "xy_point")]
    if pick is not None and pick.pose_format != "ur":
        points.append(("pick", pick.values[:3]))
    for key, point in points:
        reach = read_as_metres(point)
        if reach is not None:
            what = "The pallet frame's points are" if key.startswith("frame") else "Q is"
            lie = f"x, y, z lie within {reach:g} mm of the robot's base"
            ctx.fail(f"{path}.{key}", f"{lie}: {metres_text(reach, what)}")
    for key in ("size", "box"):  # a box or pallet no side of which reaches METRES_MAX_MM: its sizes in metres
        largest = read_as_metres(values[key])
        if largest is not None:
            shown = " x ".join(f"{v:g}" for v in values[key])
            ctx.fail(
                f"{path}.{key}",
                f"{shown} mm: given in metres? Sizes are mm: {largest:g} m is {largest * 1000.0:g} mm",
            )


def _patterns(ctx: CellValidator, patterns: dict, path: str) -> dict:
    """The patterns as read (boxes, or a family's table): at most BOXES_MAX boxes each, each box's angle within a
    turn; a family as its FamilySpec."""
    out = {}
    for key, value in patterns.items():
        where = f"{path}.{key}"
        if isinstance(value, dict):
            out[key] = FamilySpec(**value)
            continue
        if len(value) > BOXES_MAX:
            ctx.fail(where, f"{len(value)} boxes; at most {BOXES_MAX} a pattern (the most a stack may hold)")
        for i, box in enumerate(value):
            ctx.angles(box[2:], f"{where}[{i}]", what="the angle")
        out[key] = value
    return out


def pallets_of(cell) -> tuple[Pallet, ...]:
    """A cell's pallets ([[pallet]]; none: ())."""
    return cell.sections.get("pallet") or ()


__all__ = ["BOXES_MAX", "FAMILIES", "FamilySpec", "Pallet", "pallets_of", "parse_pallets"]
