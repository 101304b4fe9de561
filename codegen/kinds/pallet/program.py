"""Template variables of a pallet program: the pallet's frame, pattern tables and cycle as data, the counters and where
they are kept, the interlocks, the carried payload, the blending zone, the way home and the messages."""

from __future__ import annotations

import math

import numpy as np

from codegen import derived
from codegen.emit import EmitError, Emitter, mapped_name, owned
from codegen.kinds.pallet.analysis import frame_matrix
from codegen.kinds.pallet.cycle import (
    above_pick,
    sheet_below,
    transit_dz,
)
from codegen.kinds.pallet.interlocks import HANDSHAKES, WAITS_ON, counter_register
from codegen.kinds.pallet.kind import KIND
from codegen.kinds.pallet.messages import (
    base_message,
    counters_message,
    empty_message,
    foreign_message,
    full_message,
    known_message,
    known_question,
    lost_message,
    message_limit,
    rechecked,
    released_message,
    released_question,
    reset_held_message,
    select_message,
    still_waiting_message,
    wait_message,
)
from codegen.kinds.pallet.plan import configurations
from codegen.kinds.pallet.reach import PICK_KEY, SAFE_KEY, SHEET_ENTRY_KEY, SHEET_KEY, way_up_z
from codegen.kinds.pallet.restart import NO, YES
from codegen.kinds.pallet.section import Pallet, pallets_of
from codegen.kinds.pallet.shape import pallet_shape
from codegen.kinds.pallet.stack import sides
from codegen.model.cell import TaughtPose
from codegen.poses import rotmat_from_zyx_deg, zyx_deg_from_rotmat
from codegen.render import configuration_literal, inertia_literal
from codegen.world import loads

LEVEL_TOL = 1e-9  # a level pallet: its z is the base's z (a dialect without a pose product needs one)
POLL_S = 0.05  # how often a program looks at an interlock input while it waits for it (as the gripper's feedback)


def file_name(target, pattern: str, own: dict) -> str:
    """A file of one pallet's program: the pattern with the pallet's identifier, the store with the store's (a
    data list is named as its DEFDAT)."""
    if pattern == KIND.facts(target).get("store") and "store" in own:
        return own["store"].lower() + pattern[pattern.index(".") :]
    return pattern.format(pallet=own["ident"].lower())


def counter_registers(cell, target, index: int) -> tuple[int, int] | None:
    """The PLC registers of pallet `index`'s layer and box counters, where the controller keeps them there
    (targets/<t>.toml [program.pallet] registers; the cell's [pallet.io] registers), else None."""
    if "registers" not in KIND.facts(target):
        return None
    first = counter_register(pallets_of(cell)[index], index, target.name)
    return first, first + 1


def written_register(cell, target, index: int) -> tuple[int, str] | None:
    """The "counters written" toggle of pallet `index` (its number and name), which the program flips after each
    write of its counters and on whose change alone the PLC copies them (targets/<t>.toml [program.pallet] written:
    numbered as the layer's register), else None."""
    pattern, registers = KIND.facts(target).get("written"), counter_registers(cell, target, index)
    if pattern is None or registers is None:
        return None
    return registers[0], pattern.format(layer=registers[0])


def counter_names(cell, target, index: int) -> tuple[str, str]:
    """The names of pallet `index`'s layer and box counters (`codegen run --input`, verify): registers, or the
    identifiers of the store (each pallet's own, where the store holds several)."""
    names, registers = KIND.facts(target)["counters"], counter_registers(cell, target, index)
    if registers is not None:
        return names["layer"].format(layer=registers[0]), names["box"].format(box=registers[1])
    idents = identifiers(cell, target)[index]
    return idents["layer"], idents["box"]


def holds_name(cell, target, index: int) -> str | None:
    """The flag in pallet `index`'s store that says its program gripped what the gripper holds (set at a confirmed
    grip, cleared at a confirmed release), where the target keeps one ([program.pallet] counters.holds)."""
    if "holds" not in KIND.facts(target)["counters"]:
        return None
    return identifiers(cell, target)[index].get("holds")


def other_flags(cell, target, index: int) -> list[str]:
    """The other pallets' holds flags where this program can write them ([program.pallet] shared_flags): its grip
    clears them, so a flag left set by an item taken out by hand never makes another pallet's item look like theirs."""
    if not KIND.facts(target).get("shared_flags"):
        return []
    names = [holds_name(cell, target, i) for i in range(len(pallets_of(cell)))]
    return [name for i, name in enumerate(names) if i != index and name is not None]


def base_tolerance(pallet: Pallet) -> tuple[float, float]:
    """How far a measured pallet frame may lie from the taught points' before the program refuses it: along each axis
    the box's clearance over the stack where it travels (transit_clearance_mm, which a frame closer to the arm uses
    up; at least 0.1 mm, far above a float32 frame's rounding), about each axis the angle that moves the pallet's far
    corner as much. The reach and clearance proofs are made with the taught points' frame."""
    mm = max(pallet.transit_clearance_mm, 0.1)
    return mm, math.degrees(math.atan2(mm, math.hypot(*pallet.size)))


def base_input(cell, target, pallet: Pallet, fresh: bool = False) -> dict:
    """The controller's numbered base holding the pallet frame, where the program reads it ([pallet] base_data):
    verify's input, as the base wizard leaves it measured (the taught points' frame), or (fresh) as a controller
    whose base was never measured has it (a zero frame)."""
    facts = target.program.get("base_data")
    if pallet.base_data is None or not facts:
        return {}
    return {facts["name"].format(n=pallet.base_data): (0.0,) * 6 if fresh else _xyzabc(frame_matrix(pallet))}


def known_name(cell, target, index: int) -> str | None:
    """The flag in pallet `index`'s store that says its counters describe the pallet (FALSE as the store's file gives
    it: a reload of the store from its file brings the file's counters back), where the target keeps one
    ([program.pallet] counters.known)."""
    if "known" not in KIND.facts(target)["counters"]:
        return None
    return identifiers(cell, target)[index].get("known")


def identifiers(cell, target) -> list[dict]:
    """Per pallet, the identifiers its program uses that the cell names: the program ("pal_" and the pallet's name),
    its counters and its store; the generator's own and the counters' are taken first, so a pallet whose program
    would be named like one of them is refused (EmitError naming both)."""
    emitter = Emitter(target)
    if cell.stations_section() is not None:  # the vision program's name (and so its files' names)
        emitter.identifier("", cell.name, "the cell's program")
    for name in KIND.facts(target)["files"]:
        if "{pallet}" not in name:
            emitter.reserve(name.split(".")[0], f"the pallet task's module {name}")
    out = []
    pallets = pallets_of(cell)
    patterns = KIND.facts(target)["counters"]
    for pallet in pallets:
        own = {}
        if "{pallet}" in patterns["layer"]:  # each pallet's counters in a store of several: their own names
            for key in [k for k in ("layer", "box", "holds", "known") if k in patterns]:
                own[key] = emitter.identifier("pal_", f"{pallet.name}_{key}", f"pallet {pallet.name!r}'s {key} counter")
        elif "registers" not in KIND.facts(target):  # the program's own variables, one pair per program
            for key in ("layer", "box"):
                own[key] = emitter.reserve(patterns[key], f"the pallet counter {patterns[key]}")
        out.append(own)
    for pallet, own in zip(pallets, out, strict=True):
        own["ident"] = emitter.identifier("pal_", pallet.name, f"pallet {pallet.name!r}")
        if KIND.facts(target).get("kept_data"):  # its work object in the store, named by the pallet
            own["wobj"] = emitter.identifier("pal_", f"{pallet.name}_wobj", f"pallet {pallet.name!r}'s work object")
        if KIND.facts(target).get("task"):  # its entry routine, called from the task's main (not named as its module)
            own["entry"] = emitter.identifier("pal_", f"{pallet.name}_run", f"pallet {pallet.name!r}'s program")
        store = KIND.facts(target).get("store", "")
        if "{pallet}" in store:
            stem = store.split(".")[0].replace("{pallet}", "")
            # the name shortened (where it must be) before the stem: the store keeps its suffix, which marks it
            short = mapped_name("pal_", pallet.name, target.identifier_max - len(stem))
            own["store"] = emitter.identifier("", f"{short}{stem}", f"pallet {pallet.name!r}'s counters")
    return out


def pallet_identifiers(cell, target) -> list[str]:
    return [own["ident"] for own in identifiers(cell, target)]


def box_load(pallet: Pallet) -> loads.Load | None:
    """The box in the gripper in the TCP frame (a payload's frame): a solid box of the pallet's box size, its centre
    at box_cog_mm, its edges along the pallet's axes at box angle 0 (the tool turns with it: tool_orientation);
    None: no box mass."""
    if pallet.box_mass_kg == 0:
        return None
    centre2tcp = np.eye(4)
    centre2tcp[:3, :3] = rotmat_from_zyx_deg(*pallet.tool_orientation).T
    centre2tcp[:3, 3] = pallet.box_cog_mm
    return loads.held_box(pallet.box_mass_kg, pallet.box, centre2tcp, np.eye(4))


def carried_load(cell, pallet: Pallet) -> loads.Load | None:
    """The load while the box is in the gripper: the tool's and the box's as one, in the flange frame (mass, common
    centre of gravity, the tensor about it with the parallel-axis terms); None: no box mass or no tool given."""
    robot = cell.robot
    box = box_load(pallet)
    if robot is None or not robot.tool_given or box is None:
        return None
    return loads.combined(loads.of_tool(robot.tool, robot.tool_shaped), box.moved(robot.tool.tcp2flange))


def _xyzabc(pose) -> tuple[float, ...]:
    return tuple(float(v) for v in (*pose[:3, 3], *zyx_deg_from_rotmat(pose[:3, :3])))


def _load(emitter, load: loads.Load) -> dict:
    """A payload: mass (kg), centre of gravity in mm and in m, its inertia in the controllers' forms."""
    return {
        "mass": emitter.number(load.mass, 3),
        "cog": [emitter.number(v, 4) for v in load.cog_mm],
        "cog_m": [emitter.number(v / 1000.0, 7) for v in load.cog_mm],
        **inertia_literal(load, emitter),
    }


def pallet_context(cell, pallet: Pallet, index: int, target, emitter) -> dict:
    """Numbers in the target's notation: the frame (pallet2base), the patterns of the cycle flattened into one table
    (x, y mm, angle deg counterclockwise; each pattern's first row and count), the cycle as pattern numbers, the
    layer heights, the offsets of entry, approach and retreat, the tool's orientation at angle 0, the pick pose and
    the pose above it, the slip sheets' pick, the safe pose of the way home, the configuration of each joint move's
    pose (with an arm: chosen at generate time, codegen/kinds/pallet/posture.py), the counters and their store, the
    interlocks, the payload, the zone and the messages."""
    number = emitter.number
    limit = message_limit(cell)
    frame = pallet_shape(cell, pallet).pallet2base
    named = configurations(cell, pallet, target.name)
    own = identifiers(cell, target)[index]

    def axes(key) -> list | None:
        """A fixed pose's axis values (deg) where the program goes there as a joint target (reach.Named.anchors)."""
        if named is None or key not in named.anchors:
            return None
        return [number(float(v), 6) for v in named.anchors[key]]

    def conf(key) -> dict | None:
        return None if named is None else {**configuration_literal(target, named.values[key]), "named": named.whole}

    def pose(name: str, matrix: np.ndarray) -> list[str]:
        return emitter.pose(TaughtPose(name, _xyzabc(matrix), "xyzabc"))

    names = list(dict.fromkeys(pallet.cycle))  # each pattern once, in the cycle's order
    rows, patterns = [], []
    for name in names:
        boxes = pallet_shape(cell, pallet).layouts[name]
        patterns.append({"name": emitter.comment(name), "start": len(rows) + 1, "count": len(boxes)})
        rows.extend(
            {
                "x": number(b.x, 4),
                "y": number(b.y, 4),
                "a": number(b.ccw_deg, 4),
                # the x-y part of the approach and the retreat (the cell's, or away from the earlier boxes)
                "ax": number(ax, 4),
                "ay": number(ay, 4),
                "rx": number(rx, 4),
                "ry": number(ry, 4),
                "conf": conf((name, i)),  # the configuration of the box's entry (a joint move)
            }
            for i, (b, ((ax, ay), (rx, ry))) in enumerate(zip(boxes, sides(pallet, boxes), strict=True), start=1)
        )
    level = bool(np.allclose(frame[:3, 2], (0.0, 0.0, 1.0), atol=LEVEL_TOL))
    counts = pallet_shape(cell, pallet).layer_counts()
    first = pallet_shape(cell, pallet).items[0].key
    load, box = carried_load(cell, pallet), box_load(pallet)
    registers = counter_registers(cell, target, index)
    layer_name, box_name = counter_names(cell, target, index)
    timeout = pallet.io.timeout_s
    sheet = None
    if pallet.slip_pick is not None:
        above_sheet = pallet.slip_pick.matrix().copy()
        above_sheet[2, 3] += pallet.slip_lift
        sheet = {
            "pick": emitter.pose(pallet.slip_pick),
            "above": pose("above_sheet", above_sheet),
            "lift": number(pallet.slip_lift, 4),
            "x": number(pallet.size[0] / 2, 4),
            "y": number(pallet.size[1] / 2, 4),
            "conf": conf(SHEET_KEY) if named is not None and SHEET_KEY in named.values else None,
            "entry_conf": conf(SHEET_ENTRY_KEY) if named is not None and SHEET_ENTRY_KEY in named.values else None,
            "axes": axes(SHEET_KEY),
            "layers": [n for n in range(2, pallet.layers + 1) if sheet_below(pallet, n)],
        }
    interlocks = {
        owned(name): {
            "signal": _signal(emitter, target, signals[target.name]),
            # a wait on the supply (discharge) says so after the timeout and waits on; the others stop
            "on": name in WAITS_ON,
            "message": emitter.string(
                still_waiting_message(pallet, name, limit) if name in WAITS_ON else wait_message(pallet, name, limit)
            ),
        }
        for name, signals in pallet.io.inputs().items()
    }
    # the pallet asked for again before the carried load goes over it (it may have been taken away meanwhile)
    present = pallet.io.pallet_present[target.name]
    rechecks = {
        held: {
            "signal": _signal(emitter, target, present),
            "on": False,
            "message": emitter.string(wait_message(pallet, "pallet_present", limit, held)),
        }
        for held in rechecked(pallet)
    }
    holds = holds_name(cell, target, index)
    known = known_name(cell, target, index)
    reset = pallet.io.reset.get(target.name)
    done_out = pallet.io.done.get(target.name)
    select = pallet.io.select.get(target.name)
    handshakes = {}
    for place in HANDSHAKES:  # the zone and done outputs at Q and at the sheet dispenser (None: not given)
        outputs = pallet.io.handshake(place)
        given = all(target.name in o for o in outputs)
        handshakes[place] = (
            {
                "zone": _signal(emitter, target, outputs[0][target.name]),
                "done": _signal(emitter, target, outputs[1][target.name]),
            }
            if given
            else None
        )
    zone = pallet.zone_mm
    return {
        # the arm stops above Q (the sheet dispenser) to set the handshake's outputs at a standstill
        "handshake": handshakes,
        "name": emitter.comment(pallet.name),
        "ident": own["ident"],
        "entry": own.get("entry", own["ident"]),
        "file": own["ident"].lower(),
        "index": index + 1,
        "frame": emitter.pose(TaughtPose("frame", _xyzabc(frame), "xyzabc")),
        "frame_rotation": [[number(v, 9) for v in row] for row in frame[:3, :3]],
        "frame_origin": [number(v, 4) for v in frame[:3, 3]],
        "level": level,
        "frame_turn_deg": number(math.degrees(math.atan2(frame[1, 0], frame[0, 0])), 6),
        "rows": rows,
        "position": owned(derived.printed(target.dialect, "box")["outputs"]),  # a box's x, y on a level pallet
        "patterns": patterns,
        "cycle": [names.index(name) + 1 for name in pallet.cycle],
        "layers": pallet.layers,
        "max_count": max(counts.values()),
        "box_height": number(pallet.box[2], 4),
        "slip_every": pallet.slip_every,
        "slip_thickness": number(pallet.slip_thickness, 4),
        "sheet": sheet,
        "entry_dz": number(pallet.entry_dz, 4),
        "transit_dz": number(transit_dz(pallet), 4),  # the transit height over the layer's top (cycle.transit_dz)
        "centre": [number(pallet.size[0] / 2, 4), number(pallet.size[1] / 2, 4)],
        "approach": [number(v, 4) for v in pallet.approach],
        "retreat": [number(v, 4) for v in pallet.retreat],
        "tool_orientation": [number(v, 6) for v in pallet.tool_orientation],
        "tool": emitter.pose(TaughtPose("tool", (0.0, 0.0, 0.0, *pallet.tool_orientation), "xyzabc")),
        "pick": emitter.pose(pallet.pick),
        "pick_above": pose("above_q", above_pick(pallet)),
        "pick_lift": number(pallet.pick_lift, 4),
        "pick_conf": conf(PICK_KEY),
        "pick_axes": axes(PICK_KEY),  # above Q as a joint target (anchors), None: the pose
        "safe_axes": axes(SAFE_KEY),
        "conf_whole": named is not None and named.whole,  # else the program names only what holds (reach.py)
        "safe": pose("safe", pallet_shape(cell, pallet).safe2base),
        "safe_conf": conf(SAFE_KEY),
        "way_home_mm": number(cell.motion.retreat_mm, 4),
        # the way home rises straight up to this base z (mm, m) first: over every pallet of the arm, full or not
        "way_up_mm": number(way_up_z(cell), 4),
        "way_up_m": number(way_up_z(cell) / 1000.0, 6),
        "way_home_m": number(cell.motion.retreat_mm / 1000.0, 6),
        "registers": registers,
        "written": None if (toggle := written_register(cell, target, index)) is None else toggle[0],
        "counters": {"layer": owned(layer_name), "box": owned(box_name)},  # Code already, or a register's name
        "holds": None if holds is None else owned(holds),  # the flag: this program gripped what the gripper holds
        # the flag: the counters describe the pallet (FALSE as the store's file gives it)
        "known": None if known is None else owned(known),
        "known_question": emitter.string(known_question(pallet, limit)),
        "known_message": emitter.string(known_message(pallet, limit)),
        # the other pallets' flags this program can write, cleared by its grip
        "other_holds": [owned(name) for name in other_flags(cell, target, index)],
        "base": _base(cell, pallet, target, emitter),
        "foreign": emitter.string(foreign_message(pallet, limit)),
        "lost": emitter.string(lost_message(pallet, limit)),
        "store": own.get("store"),
        "wobj": own.get("wobj"),  # the pallet's work object in the store (None: in the program's own data)
        "store_file": _store_file(target, own),  # the file of the counters (None: they are not kept in one)
        "start": {"layer": first[0], "box": first[1]},
        "auto": pallet.approach_auto,
        "unstack": pallet.mode == "unstack",  # take the boxes off, top layer first, each layer in reverse
        "top_count": counts[pallet.layers],
        "load": None if load is None else _load(emitter, load),
        "box_load": None if box is None else _load(emitter, box),
        "zone": None if zone == 0 else {"mm": number(zone, 1), "m": number(zone / 1000.0, 4)},
        "zone_ori_mm": number(1.5 * zone, 1),  # a RAPID zonedata scaled as the predefined zN are: 1.5 N mm, 0.15 N deg
        "zone_deg": number(0.15 * zone, 2),
        "joint_blend": KIND.facts(target).get("joint_blend", True) and zone > 0,
        "interlocks": interlocks,
        "rechecks": rechecks,
        "check_zone": not KIND.facts(target).get("input_stops", False),  # a move before an input's check may blend
        "timeout_s": number(timeout, 3),
        "timeout_text": emitter.comment(f"{timeout:g}"),
        "polls": signal_polls_for(timeout),
        "poll_s": number(POLL_S, 2),
        "reset": None if reset is None else _signal(emitter, target, reset),
        # the output on while the pallet is full (empty); turned off to answer the PLC's reset
        "done_out": None if done_out is None else _signal(emitter, target, done_out),
        "reset_held": emitter.string(reset_held_message(pallet, limit)),
        # stacking, after a stop during a release: the operator's question (where the target asks), else a stop
        "asks": bool(KIND.facts(target).get("asks")),
        # s the operator has to answer it before the program stops with its message (None: it waits)
        "asks_within_s": None if (within := KIND.facts(target).get("asks_within_s")) is None else number(within, 1),
        # the looks at a dialog 0.1 s apart within asks_within_s (a program that polls for the answer)
        "ask_polls": None if within is None else math.ceil(within / 0.1 - 1e-9),
        "question": emitter.string(released_question(pallet, limit)),
        "released": emitter.string(released_message(pallet, limit)),
        "yes": emitter.string(YES),
        "no": emitter.string(NO),
        "select": None if select is None else _signal(emitter, target, select),
        "empty": emitter.string(empty_message(pallet, limit)),
        "full": emitter.string(full_message(pallet, limit)),
        "bad_counters": emitter.string(counters_message(pallet, limit)),
        "release": emitter.comment(target.program.get("minimum_release", "")),
    }


def _base(cell, pallet: Pallet, target, emitter) -> dict | None:
    """The numbered base the program reads the pallet frame from, the tolerance it checks it with and its message."""
    facts = target.program.get("base_data")
    if pallet.base_data is None or not facts:
        return None
    name = facts["name"].format(n=pallet.base_data)
    mm, deg = base_tolerance(pallet)
    return {
        "name": owned(name),
        "mm": emitter.number(mm, 3),
        "deg": emitter.number(deg, 4),
        "message": emitter.string(base_message(pallet, pallet.base_data, message_limit(cell))),
    }


def _store_file(target, own: dict) -> str | None:
    """The file the counters are kept in, where the target keeps them in a file of their own (its facts' store)."""
    store = KIND.facts(target).get("store", "")
    return owned(file_name(target, store, own)) if "." in store else None


def signal_polls_for(timeout_s: float) -> int:
    return math.ceil(timeout_s / POLL_S - 1e-9)


def _signal(emitter, target, value) -> str:
    """An input as the program names it: its number, or its configured name (an identifier of the program)."""
    if isinstance(value, int):
        return emitter.number(value, 0)
    return emitter.identifier("", value, f"the signal {value}")


def task_context(cell, target, emitter, contexts: list[dict]) -> dict:
    """What the task's own modules print (a controller whose pallet programs share one task): the main module
    starting the program whose select input is on, and the store of every pallet's counters."""
    return {
        "pallets": contexts,
        "no_select": emitter.string(select_message()),
        "main": owned(KIND.facts(target)["files"][0].split(".")[0]),
        "data": owned(KIND.facts(target)["store"].split(".")[0]),
    }


def check_level(pallet: Pallet, target) -> None:
    """A dialect without a pose product places boxes on a level pallet only."""
    if KIND.facts(target).get("level_only") and not np.allclose(
        frame_matrix(pallet)[:3, 2], (0.0, 0.0, 1.0), atol=LEVEL_TOL
    ):
        raise EmitError(
            f"pallet {pallet.name!r}: the {target.name} program needs a level pallet (its z the base's z): "
            "the dialect has no pose product to tilt the boxes"
        )


__all__ = [
    "carried_load",
    "check_level",
    "counter_names",
    "counter_registers",
    "file_name",
    "holds_name",
    "identifiers",
    "known_name",
    "pallet_context",
    "pallet_identifiers",
    "task_context",
    "written_register",
]
