"""The [[pallet]] tables of a cell file, validated (file, key path; exit 2 through CellError)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from codegen.kinds.pallet.interlocks import PalletIO, check_pallets_io, parse_io
from codegen.kinds.pallet.keys import FAMILIES, FAMILY, FRAME, MAX_LAYERS, MAX_SIZE_MM, PALLET, SLIP_SHEET
from codegen.model.cell import CellValidator

PALLET_KEYS = PALLET.allowed
FRAME_KEYS = FRAME.allowed
FAMILY_KEYS = FAMILY.allowed
SLIP_KEYS = SLIP_SHEET.allowed
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
MAX_PICK_LIFT_MM = PALLET["pick_lift"].high


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


def parse_pallets(ctx: CellValidator, data: dict, cell) -> tuple[Pallet, ...]:
    """The [[pallet]] tables of a cell file (cell: as far as it is known: pose format, targets, motion)."""
    raw = data.get("pallet", [])
    if not isinstance(raw, list) or not all(isinstance(t, dict) for t in raw):
        ctx.fail("pallet", "expected [[pallet]] tables")
    pallets = tuple(_pallet(ctx, table, f"pallet[{i}]", cell) for i, table in enumerate(raw))
    names = [p.name for p in pallets]
    for i, name in enumerate(names):
        if name in names[:i]:
            ctx.fail(f"pallet[{i}].name", f"pallet {name!r} named twice")
    check_pallets_io(ctx, pallets, cell.targets)
    return pallets


def _positive(ctx: CellValidator, values, count: int, path: str, limit: float = MAX_SIZE_MM) -> tuple[float, ...]:
    numbers = ctx.numbers(values, count, path)
    if not all(0 < v <= limit for v in numbers):
        ctx.fail(path, f"every value must be in (0, {limit:g}] mm")
    return numbers


def _pallet(ctx: CellValidator, table: dict, path: str, cell) -> Pallet:
    pose_format = cell.pose_format
    ctx.no_unknown(table, PALLET_KEYS, path)
    name = ctx.name(table, "name", f"{path}.name")
    frame = ctx.table(table, "frame", f"{path}.frame")
    ctx.no_unknown(frame, FRAME_KEYS, f"{path}.frame")
    points = [ctx.point(ctx.require(frame, k, f"{path}.frame.{k}"), f"{path}.frame.{k}") for k in sorted(FRAME_KEYS)]
    origin, x_point, xy_point = points  # sorted: origin, x_point, xy_point
    size = _positive(ctx, ctx.require(table, "size", f"{path}.size"), 2, f"{path}.size")
    box = _positive(ctx, ctx.require(table, "box", f"{path}.box"), 3, f"{path}.box")
    layers = ctx.integer(table, "layers", f"{path}.layers", 1, MAX_LAYERS)
    patterns = _patterns(ctx, ctx.table(table, "patterns", f"{path}.patterns"), f"{path}.patterns")
    cycle = ctx.require(table, "cycle", f"{path}.cycle")
    if not isinstance(cycle, list) or not cycle:
        ctx.fail(f"{path}.cycle", "expected a non-empty list of pattern names")
    if len(cycle) > MAX_LAYERS:
        ctx.fail(f"{path}.cycle", f"{len(cycle)} patterns; at most {MAX_LAYERS}, the most layers a stack has")
    for i, entry in enumerate(cycle):
        if not isinstance(entry, str) or entry not in patterns:
            ctx.fail(f"{path}.cycle[{i}]", f"no pattern {entry!r}; the patterns: {', '.join(patterns)}")
    sense = table.get("angle_sense", PALLET.default("angle_sense"))
    if sense not in PALLET["angle_sense"].choices:
        ctx.fail(f"{path}.angle_sense", 'expected "cw" (clockwise, as source 004\'s editor) or "ccw"')
    where = f"{path}.tool_orientation"
    orientation = ctx.angles(
        ctx.numbers(table.get("tool_orientation", list(PALLET.default("tool_orientation"))), 3, where), where
    )
    entry_dz = ctx.number(table, "entry_dz", f"{path}.entry_dz")
    if not 0 < entry_dz <= MAX_SIZE_MM:
        ctx.fail(f"{path}.entry_dz", f"must be in (0, {MAX_SIZE_MM:g}] mm: the entry is above the target")
    approach = _offset(ctx, ctx.require(table, "approach", f"{path}.approach"), f"{path}.approach")
    retreat = _offset(ctx, table.get("retreat", list(approach)), f"{path}.retreat")
    # the pick pose Q, base frame, in the cell's pose format
    pick = ctx.pose("pick", ctx.require(table, "pick", f"{path}.pick"), f"{path}.pick", pose_format)
    pick_lift = ctx.finite(table.get("pick_lift", PICK_LIFT_MM), f"{path}.pick_lift")
    if not 0 < pick_lift <= MAX_PICK_LIFT_MM:
        ctx.fail(f"{path}.pick_lift", f"must be in (0, {MAX_PICK_LIFT_MM:g}] mm: the lift straight up from Q")
    overhang = ctx.finite(table.get("overhang_mm", PALLET.default("overhang_mm")), f"{path}.overhang_mm")
    if not PALLET["overhang_mm"].contains(overhang):
        ctx.fail(f"{path}.overhang_mm", "must be in [0, 200] mm")
    transit = ctx.finite(
        table.get("transit_clearance_mm", PALLET.default("transit_clearance_mm")), f"{path}.transit_clearance_mm"
    )
    if not PALLET["transit_clearance_mm"].contains(transit):
        ctx.fail(f"{path}.transit_clearance_mm", f"must be in [0, {MAX_SIZE_MM:g}] mm")
    support = ctx.finite(table.get("support_min", PALLET.default("support_min")), f"{path}.support_min")
    if not PALLET["support_min"].contains(support):
        ctx.fail(f"{path}.support_min", "must be a share in [0, 1]")
    slip_every, slip_thickness, slip_pick, slip_lift = 0, 0.0, None, SLIP_SHEET.default("lift")
    if "slip_sheet" in table:
        slip = ctx.table(table, "slip_sheet", f"{path}.slip_sheet")
        ctx.no_unknown(slip, SLIP_KEYS, f"{path}.slip_sheet")
        slip_every = ctx.integer(slip, "every", f"{path}.slip_sheet.every", 1, MAX_LAYERS)  # on every n-th layer
        slip_thickness = ctx.number(slip, "thickness", f"{path}.slip_sheet.thickness")
        if not SLIP_SHEET["thickness"].contains(slip_thickness):
            ctx.fail(f"{path}.slip_sheet.thickness", "must be in (0, 50] mm")
        if table.get("mode", PALLET.default("mode")) == "unstack":
            ctx.fail(
                f"{path}.slip_sheet",
                "an unstacking program would grip the slip sheet on a layer with its box: codegen places slip "
                "sheets when stacking only",
            )
        where = f"{path}.slip_sheet.pick"
        slip_pick = ctx.pose("slip_pick", ctx.require(slip, "pick", where), where, pose_format)
        slip_lift = ctx.finite(slip.get("lift", slip_lift), f"{path}.slip_sheet.lift")
        if not SLIP_SHEET["lift"].contains(slip_lift):
            ctx.fail(
                f"{path}.slip_sheet.lift", f"must be in {SLIP_SHEET['lift'].range_text()} mm: straight up from the pick"
            )
    auto = table.get("approach_auto", PALLET.default("approach_auto"))
    if not isinstance(auto, bool):
        ctx.fail(f"{path}.approach_auto", "must be true or false")
    if auto and min(math.hypot(*approach[:2]), math.hypot(*retreat[:2])) < 1.0:
        ctx.fail(f"{path}.approach_auto", "turns the x-y part of approach and retreat: each needs one of 1 mm or more")
    mode = table.get("mode", PALLET.default("mode"))
    if mode not in PALLET["mode"].choices:
        ctx.fail(f"{path}.mode", 'expected "stack" (place the boxes) or "unstack" (take them off, top layer first)')
    io_table = ctx.table(table, "io", f"{path}.io") if "io" in table else None
    io = parse_io(ctx, io_table, path, cell.targets, mode, slip_pick is not None)
    mass = ctx.finite(table.get("box_mass_kg", PALLET.default("box_mass_kg")), f"{path}.box_mass_kg")
    if not PALLET["box_mass_kg"].contains(mass):
        ctx.fail(f"{path}.box_mass_kg", f"must be in {PALLET['box_mass_kg'].range_text()} kg")
    cog = (0.0, 0.0, box[2] / 2)  # the TCP on the box's top, its z into the box: the box's centre
    if "box_cog_mm" in table:
        cog = ctx.numbers(table["box_cog_mm"], 3, f"{path}.box_cog_mm")
        if max(abs(v) for v in cog) > MAX_SIZE_MM:
            ctx.fail(f"{path}.box_cog_mm", f"every value must be within +-{MAX_SIZE_MM:g} mm")
    zone = ctx.finite(table.get("zone_mm", cell.motion.zone_mm), f"{path}.zone_mm")
    if not PALLET["zone_mm"].contains(zone):
        ctx.fail(f"{path}.zone_mm", f"must be in {PALLET['zone_mm'].range_text()} mm")
    return Pallet(
        name,
        origin,
        x_point,
        xy_point,
        size,
        box,
        layers,
        tuple(cycle),
        sense,
        orientation,
        entry_dz,
        approach,
        retreat,
        pick,
        patterns,
        overhang,
        support,
        slip_every,
        slip_thickness,
        mode,
        auto,
        pick_lift,
        io,
        mass,
        cog,
        slip_pick,
        slip_lift,
        zone,
        transit,
    )


def _offset(ctx: CellValidator, values, path: str) -> tuple[float, float, float]:
    numbers = ctx.numbers(values, 3, path)
    if max(abs(v) for v in numbers) > MAX_SIZE_MM:
        ctx.fail(path, f"every value must be within +-{MAX_SIZE_MM:g} mm")
    if numbers[2] <= 0:
        ctx.fail(path, "z must be above the target (> 0): the arm comes from above")
    return numbers


def _patterns(ctx: CellValidator, table: dict, path: str) -> dict:
    if not table:
        ctx.fail(path, "expected at least one pattern")
    out = {}
    for key, value in table.items():
        where = f"{path}.{key}"
        if isinstance(value, dict):
            ctx.no_unknown(value, FAMILY_KEYS, where)
            family = ctx.require(value, "family", f"{where}.family")
            if family not in FAMILIES:
                ctx.fail(f"{where}.family", f"unknown family {family!r}; known: {', '.join(FAMILIES)}")
            flags = {}
            for flag in ("mirror", "label_out"):
                flags[flag] = value.get(flag, FAMILY.default(flag))
                if not isinstance(flags[flag], bool):
                    ctx.fail(f"{where}.{flag}", "must be true or false")
            out[key] = FamilySpec(family, **flags)
        elif isinstance(value, list) and value:
            if len(value) > BOXES_MAX:
                ctx.fail(where, f"{len(value)} boxes; at most {BOXES_MAX} a pattern (the most a stack may hold)")
            boxes = tuple(ctx.numbers(box, 3, f"{where}[{i}]") for i, box in enumerate(value))
            for i, box in enumerate(boxes):
                if max(abs(v) for v in box[:2]) > MAX_SIZE_MM:
                    ctx.fail(f"{where}[{i}]", f"x, y within +-{MAX_SIZE_MM:g} mm")
                ctx.angles(box[2:], f"{where}[{i}]", what="the angle")
            out[key] = boxes
        else:
            ctx.fail(where, "expected a list of [x, y, angle] boxes or a table { family = ... }")
    return out


def pallets_of(cell) -> tuple[Pallet, ...]:
    """A cell's pallets ([[pallet]]; none: ())."""
    return cell.sections.get("pallet") or ()


__all__ = ["BOXES_MAX", "FAMILIES", "FamilySpec", "Pallet", "pallets_of", "parse_pallets"]
