"""The float64 reference of a pallet program's cycle: from the counters each move, output and stop to the end."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from codegen.guard import NO_FEEDBACK, NOT_RELEASED, halt_message
from codegen.kinds.pallet.analysis import frame_matrix
from codegen.kinds.pallet.interlocks import HANDSHAKES, WAITS_ON
from codegen.kinds.pallet.messages import (
    lost_message,
    message_limit,
    still_waiting_message,
    wait_message,
)
from codegen.kinds.pallet.section import Pallet
from codegen.kinds.pallet.stack import Placement, layer_top, placements
from codegen.poses import matrix_from_rotation_translation, rotmat_from_zyx_deg

__all__ = [
    "SAFE_NAME",
    "Expected",
    "ExpectedMove",
    "Item",
    "PalletCase",
    "Run",
    "above_pick",
    "items",
    "layer_counts",
    "risen",
    "safe_pose",
    "stacking",
    "start_counters",
    "transit_dz",
    "transit_pose",
    "unstacking",
]


SAFE_NAME = "safe above the pallet"  # the joint move above the pallet's centre (safe_pose): the way home, a restart


@dataclass(frozen=True)
class PalletCase:
    """A run of the pallet program: its counters when it starts, how the gripper answers, an interlock input that
    never comes on (None: each is on), whether the PLC's reset input is on."""

    category: str
    layer: int
    box: int
    gripper: str = "prompt"  # codegen.sim.gripper.Gripper behaviours
    closed: bool = False  # the gripper's sensor on at the start: it holds a box (a cycle stopped mid-way)
    # an interlock (codegen/kinds/pallet/interlocks.py WAITS) whose input stays off (one of WAITS_ON: until the program
    # said it waits on)
    missing: str | None = None
    reset: bool = False  # the PLC asks for the counters of a swapped pallet to start again
    reset_held: bool = False  # the PLC keeps that reset on after the program's answer (a level input, not a request)
    # stacking, the counters marked as a stop during a release leaves them (layer negative): the operator's answer to
    # "is the item down?" (YES, NO), None: the program cannot ask (it stops with a message)
    answer: str | None = None
    foreign: bool = False  # the item held at the start was gripped by another pallet's program of the same arm
    stale: bool = False  # another pallet's flag left set (its item taken out by hand): cleared by this program's grip
    base_off: bool = False  # the controller's numbered base the program reads the pallet frame from is not measured
    lost: bool = False  # the first item gripped slips out of the gripper on its way to the pallet
    taken: bool = False  # the pallet is taken away once the first grip is made (the arm at the pick place)
    # the counters' store loaded again from its file (as a reset of RAPID does): the counters are the file's, its
    # known flag FALSE; the pallet may be part-built, so only the PLC's reset or the operator's Yes starts it
    unknown: bool = False
    # with unknown: the PLC's reset comes on while the operator is asked (and nobody answers): it ends the question
    # (RAPID TPReadFK \DIBreak) and its handshake starts the pallet
    reset_asked: bool = False
    # the pallets the PLC swaps once one is done (the program waits above Q for each swap's reset, then works the new
    # one); with exchange_held the PLC keeps that reset on after the program's answer
    exchanges: int = 0
    exchange_held: bool = False


@dataclass(frozen=True, kw_only=True)
class ExpectedMove:
    kind: str  # "joint" or "linear"
    tcp2base: np.ndarray  # 4x4 mm
    name: str  # for the report: "layer 2 box 3 entry"
    speed_mm_s: float
    exact: bool  # a stop at the pose (no blending): a pick, place or contact pose, or where a wait follows
    carrying: bool = False  # a box in the gripper (its grip confirmed): the payload is the tool's and the box's
    checked: bool = False  # an interlock input is read right after it (where that read stops the advance run, a stop)
    sheet: bool = False  # a slip sheet in the gripper (weightless: no payload; its sweep is checked as a box's)
    joints: np.ndarray | None = None  # the arm's joints there, where known (the sweep follows a joint move by them)


@dataclass(frozen=True)
class Expected:
    moves: tuple[ExpectedMove, ...]
    # (which output: "gripper" or "done", its value, moves commanded before it); "done" is the pallet's full (empty)
    # output, where the cell gives one
    outputs: tuple[tuple[str, bool, int], ...]
    halt: str | None  # the operator's message, None: the program ends (the pallet is full or empty)
    counters: tuple[int, int]  # layer and box when the run ends: what to do next
    start: tuple[int, int] = (0, 0)  # the counters the program worked from (after a reset)
    said: tuple[str, ...] = ()  # the notifications of a wait on the supply that lasted the timeout (it waited on)
    asked: bool = False  # the operator was asked whether an item released before a stop is down
    holds: bool = False  # at the end, the gripper holds an item this program gripped (its store's flag)
    gripped: bool = False  # the program confirmed a grip (where one task runs every pallet: the others' flags cleared)
    known: bool = True  # at the end, the store's flag: its counters describe the pallet
    known_asked: bool = False  # the operator was asked whether the pallet is new (the store reloaded from its file)
    exchanged: tuple[int, ...] = ()  # the moves commanded when each swap's reset came (the arm waiting above Q)
    waits: bool = False  # the run ends with the program above Q waiting for the done pallet's swap (the PLC's reset)


@dataclass(frozen=True)
class Item:
    """One thing the program does on the pallet, named by the counters: a box (number >= 1) or the slip sheet
    below a layer (number 0)."""

    layer: int
    number: int
    placement: Placement | None  # None: the slip sheet

    @property
    def key(self) -> tuple[int, int]:
        return self.layer, self.number


def layer_counts(pallet: Pallet) -> dict[int, int]:
    counts: dict[int, int] = {}
    for p in placements(pallet):
        counts[p.layer] = counts.get(p.layer, 0) + 1
    return counts


def sheet_below(pallet: Pallet, layer: int) -> bool:
    """A slip sheet to place below this layer (on top of every slip_every-th layer, when the cell gives its pick)."""
    return pallet.slip_pick is not None and layer > 1 and (layer - 1) % pallet.slip_every == 0


def items(pallet: Pallet) -> list[Item]:
    """What the program does, in its order: stacking, layer by layer from the bottom, the sheet below a layer
    first; unstacking, the reverse (no sheets)."""
    out = []
    for p in placements(pallet):
        if p.number == 1 and sheet_below(pallet, p.layer):
            out.append(Item(p.layer, 0, None))
        out.append(Item(p.layer, p.number, p))
    return out if pallet.mode == "stack" else out[::-1]


def start_counters(pallet: Pallet) -> tuple[int, int]:
    """The counters of a new pallet: stacking layer 1 box 1, unstacking the top layer's last box."""
    return items(pallet)[0].key


def done_counters(pallet: Pallet) -> tuple[int, int]:
    """The counters once the pallet is full (layers + 1, box 1) or empty (0, 0)."""
    return (pallet.layers + 1, 1) if pallet.mode == "stack" else (0, 0)


def above_pick(pallet: Pallet) -> np.ndarray:
    """Q lifted by pick_lift along the base's z (tcp2base, mm): where the arm comes down to Q from and
    lifts the box back to."""
    above = pallet.pick.matrix().copy()
    above[2, 3] += pallet.pick_lift
    return above


def _tool(pallet: Pallet) -> np.ndarray:
    return rotmat_from_zyx_deg(*pallet.tool_orientation)


def sheet_target(pallet: Pallet, layer: int) -> np.ndarray:
    """The slip sheet below a layer, in the pallet frame: the gripper on the sheet's top at the pallet's centre,
    the tool as at box angle 0."""
    z = layer_top(pallet, layer - 1) + pallet.slip_thickness
    return matrix_from_rotation_translation(_tool(pallet), (pallet.size[0] / 2, pallet.size[1] / 2, z))


def safe_pose(pallet: Pallet) -> np.ndarray:
    """Above the pallet's centre at the transit height over the full stack (pallet frame): the way home after a stop
    passes it, a held box clear of the stack's top by transit_clearance_mm as on every transit."""
    z = layer_top(pallet, pallet.layers) + transit_dz(pallet)
    return matrix_from_rotation_translation(_tool(pallet), (pallet.size[0] / 2, pallet.size[1] / 2, z))


def transit_dz(pallet: Pallet) -> float:
    """How high over the top of the layer a box goes onto (is taken from) the carried box travels: its height and
    transit_clearance_mm, or the entry's height if that is higher."""
    return max(pallet.box[2] + pallet.transit_clearance_mm, pallet.entry_dz)


def transit_pose(pose: np.ndarray, pallet: Pallet, layer: int) -> np.ndarray:
    """A pose (pallet frame) raised to the transit height over the top of the layer: above the entry."""
    out = pose.copy()
    out[2, 3] = layer_top(pallet, layer) + transit_dz(pallet)
    return out


def risen(pose: np.ndarray, z: float) -> np.ndarray:
    """A pose (base frame) raised straight up to the base's z (kept where it is higher already)."""
    out = pose.copy()
    out[2, 3] = max(out[2, 3], z)
    return out


def _lifted(pose: np.ndarray, mm: float) -> np.ndarray:
    out = pose.copy()
    out[2, 3] += mm
    return out


class Run:
    """The reference's record of one run: moves, gripper outputs, where it stops and the counters."""

    def __init__(self, cell, pallet: Pallet, case: PalletCase, counters: tuple[int, int]) -> None:
        self.cell, self.pallet, self.case = cell, pallet, case
        self.frame = frame_matrix(pallet)
        self.travel, self.work = cell.motion.speed_mm_s, cell.motion.work_speed_mm_s
        self.moves: list[ExpectedMove] = []
        self.outputs: list[tuple[str, bool, int]] = [("gripper", not cell.io.value, 0)]  # released at the start
        self.counters = counters
        self.carrying = False
        self.gripped = False  # a grip made (the pallet may be taken away after it: case.taken)
        self.sheet = False  # a slip sheet in the gripper
        self.holds = case.closed  # this program gripped what the gripper holds (a held item at the start: its own)
        self.said: list[str] = []  # the waits on the supply that lasted the timeout: their notifications

    def move(self, kind: str, pose: np.ndarray, name: str, slow: bool, exact: bool) -> None:
        speed = self.work if slow else self.travel
        self.moves.append(
            ExpectedMove(
                kind=kind,
                tcp2base=pose,
                name=name,
                speed_mm_s=speed,
                exact=exact,
                carrying=self.carrying,
                sheet=self.sheet,
            )
        )

    def wait(self, interlock: str, held: str | None = None) -> str | None:
        """The program waits for an interlock input (held: what is in the gripper meanwhile, for the message): the
        stop's message if it never comes on."""
        if self.moves:
            self.moves[-1] = replace(self.moves[-1], checked=True)
        taken = interlock == "pallet_present" and self.case.taken and self.gripped
        if self.case.missing != interlock and not taken:
            return None
        if interlock in WAITS_ON:  # a gap in the supply (discharge): said once, then the program waits on
            if not self.said:
                self.said.append(still_waiting_message(self.pallet, interlock, message_limit(self.cell)))
            return None
        return wait_message(self.pallet, interlock, message_limit(self.cell), held)

    def handshake(self, place: str, entering: bool) -> None:
        """The arm at its stop above a place ("q" or "sheet"), where the cell gives that place's handshake: going in,
        the zone output on and the done output off; come out, the zone output off and the done output on. An output
        is set at a standstill, so the move before it stops exactly at its pose."""
        zone, done = HANDSHAKES[place]
        if not getattr(self.pallet.io, zone):
            return
        self.arrive(place)
        after = len(self.moves)
        self.outputs += [(zone, entering, after), (done, not entering, after)]

    def arrive(self, place: str) -> None:
        """Above a place whose handshake the cell gives: the arm stops there (its waits and the outputs follow)."""
        if getattr(self.pallet.io, HANDSHAKES[place][0]):
            self.moves[-1] = replace(self.moves[-1], exact=True)

    def zones_off(self) -> None:
        """At the start, once home (a stop in a zone may have left its output on): every zone output off."""
        for zone, _ in HANDSHAKES.values():
            if getattr(self.pallet.io, zone):
                self.outputs.append((zone, False, len(self.moves)))

    def grip(self, box: bool = True) -> str | None:
        """Grip a box (its payload from the confirmed grip on) or a slip sheet (light: the tool's payload stays)."""
        self.outputs.append(("gripper", self.cell.io.value, len(self.moves)))
        if self.case.gripper == "silent":  # opened again before the stop: nothing carried off half-held
            self.outputs.append(("gripper", not self.cell.io.value, len(self.moves)))
            return halt_message(self.cell, NO_FEEDBACK, None, 0)
        self.carrying, self.sheet, self.gripped, self.holds = box, not box, True, True
        return None

    def release(self) -> str | None:
        self.outputs.append(("gripper", not self.cell.io.value, len(self.moves)))
        if self.case.gripper == "stuck":
            return halt_message(self.cell, NOT_RELEASED, None, 0)
        self.carrying = self.sheet = self.holds = False
        return None

    def result(self, halt: str | None, start: tuple[int, int]) -> Expected:
        said = tuple(self.said)
        out = Expected(tuple(self.moves), tuple(self.outputs), halt, self.counters, start, said, holds=self.holds)
        return replace(out, gripped=self.gripped)


def stacking(run: Run, todo: list[Item], done: tuple[int, int]) -> str | None:
    """Per box: (after the item before it, the empty gripper from that entry over Q at the entry's height, joint, then
    straight down) above Q (the pallet and a box at Q waited for), Q (slow, exact), grip, above Q (slow), up to the
    transit height (transit_pose: the box clear of the layer's top), the pallet waited for again (it may have been
    taken away while the arm was at Q), above the entry at that height (joint), the entry, approach (slow), target
    (slow, exact), release, retreat (slow), entry; the counters advance once the release is confirmed. Per slip sheet
    the same from the sheet stack onto the pallet's centre (the transit height over the sheet's place: its top +
    transit_dz). At the end: over Q at the last entry's height (joint), above Q, off the pallet, before the
    message. The gripper, empty or holding a box, crosses the stack only above the entry or transit height."""
    pallet, frame = run.pallet, run.frame
    pick, above = pallet.pick.matrix(), above_pick(pallet)
    joint = "transit"  # the joint move onto the pallet: above the entry at the transit height
    height = 0.0  # the entry the empty gripper leaves the pallet from (base z, mm)
    for i, item in enumerate(todo):
        after = todo[i + 1].key if i + 1 < len(todo) else done
        where = f"layer {item.layer} " + (f"box {item.number}" if item.number else "sheet")
        if item.placement is None:  # like a box: up to the transit height, over the sheet's place, straight down
            source, lift = pallet.slip_pick.matrix(), pallet.slip_lift
            placed = sheet_target(pallet, item.layer)
            entry = frame @ _lifted(placed, pallet.entry_dz)
            transit = frame @ _lifted(placed, transit_dz(pallet))
            path = (
                (risen(_lifted(source, lift), transit[2, 3]), "up from the sheet stack", False, False),
                (transit, "transit", False, False),
                (entry, "entry", False, False),
                (frame @ placed, "target", True, True),
            )
            retreat = ((entry, "entry", True, False),)
            interlocks, named = ("pallet_present", "sheet_ready"), "the sheet stack"
        else:
            p = item.placement
            source, lift = pick, pallet.pick_lift
            transit = frame @ transit_pose(p.entry, pallet, p.layer)
            path = (
                (risen(_lifted(source, lift), transit[2, 3]), "up from Q", False, False),
                (transit, "transit", False, False),
                (frame @ p.entry, "entry", False, False),
                (frame @ p.approach, "approach", True, False),
                (frame @ p.target, "target", True, True),
            )
            retreat = ((frame @ p.retreat, "retreat", True, False), (frame @ p.entry, "entry", False, False))
            interlocks, named = ("pallet_present", "part_present"), "Q"
        if i == 0 and (run.carrying or run.sheet):  # held at the start: from home onto its place
            halt = run.wait("pallet_present", "box" if item.placement is not None else "sheet")
            if halt:
                return halt
            # first above the pallet's centre as a joint target (the safe pose, in the cycle's turns): the joint move
            # onto the transit then takes the turn the cycle has there, not the one nearest home
            run.move("joint", frame @ safe_pose(pallet), SAFE_NAME, False, True)
            for pose, name, slow, exact in path[1:]:
                run.move("joint" if name == joint else "linear", pose, f"{where} {name}", slow, exact)
            halt, height = _release_and_back_out(run, retreat, item.key, after, where)
            if halt:
                return halt
            continue
        if i > 0:  # the empty gripper at the entry before: over the pick at that height first, then down to it
            run.move("joint", risen(_lifted(source, lift), height), f"{where} over {named}", False, False)
            run.move("linear", _lifted(source, lift), f"{where} above {named}", False, False)
        else:
            run.move("joint", _lifted(source, lift), f"{where} above {named}", False, False)
        place = "q" if item.placement is not None else "sheet"
        run.arrive(place)
        for interlock in interlocks:
            halt = run.wait(interlock)
            if halt:
                return halt
        run.handshake(place, True)
        run.move("linear", source, f"{where} pick", True, True)
        halt = run.grip(item.placement is not None)
        if halt:
            return halt
        run.move("linear", _lifted(source, lift), f"{where} lift from {named}", True, False)
        run.handshake(place, False)
        for pose, name, slow, exact in path:
            if name == joint:  # the pallet still in place before the load goes over it (taken away meanwhile?)
                halt = run.wait("pallet_present", "box" if item.placement is not None else "sheet")
                if halt:
                    return halt
            run.move("joint" if name == joint else "linear", pose, f"{where} {name}", slow, exact)
        halt, height = _release_and_back_out(run, retreat, item.key, after, where)
        if halt:
            return halt
    run.move("joint", risen(above, height), "off the pallet: over Q", False, False)
    run.move("linear", above, "off the pallet: above Q", False, True)
    return None


def unstacking(run: Run, todo: list[Item], done: tuple[int, int], from_q: bool = False) -> str | None:
    """The pallet waited for first; per box, the top layer first and each layer in the reverse of its placing
    order: (after the box before it: straight up over Q to this box's transit height) above the entry at the transit
    height (transit_pose, joint), entry, approach (slow), target (slow, exact), grip; once the grip is confirmed the
    counters are marked (the layer negative); retreat (slow), entry, up to the transit height, over Q at that height
    (joint), above Q (Q clear waited for), Q (slow, exact); the sensor still on (the box not dropped on the way), the
    counters move to the next box, release; above Q (slow); for the next box the pallet waited for there, out of
    Q's zone. The empty gripper, like the carried box, crosses the stack only at the transit height. from_q: the arm
    starts above Q (a held box put down there first)."""
    pallet, frame = run.pallet, run.frame
    pick, above = pallet.pick.matrix(), above_pick(pallet)
    halt = run.wait("pallet_present")
    if halt:
        return halt
    for i, item in enumerate(todo):
        p, last = item.placement, i + 1 == len(todo)
        where = f"layer {p.layer} box {p.number}"
        transit = frame @ transit_pose(p.entry, pallet, p.layer)
        if i > 0 or from_q:  # the arm above Q, empty: straight up to this box's transit height first
            run.move("linear", risen(above, transit[2, 3]), f"{where} up from Q", False, False)
        run.move("joint", transit, f"{where} transit", False, False)
        run.move("linear", frame @ p.entry, f"{where} entry", False, False)
        run.move("linear", frame @ p.approach, f"{where} approach", True, False)
        run.move("linear", frame @ p.target, f"{where} target", True, True)
        halt = run.grip()
        if halt:
            return halt
        run.counters = (-p.layer, p.number)  # marked until the box reaches Q: a stop meanwhile leaves the question
        run.move("linear", frame @ p.retreat, f"{where} retreat", True, False)
        run.move("linear", frame @ p.entry, f"{where} entry", False, False)
        run.move("linear", transit, f"{where} transit", False, False)
        run.move("joint", risen(above, transit[2, 3]), f"{where} over Q", False, False)
        run.move("linear", above, f"{where} above Q", False, False)
        run.arrive("q")
        halt = run.wait("place_clear")
        if halt:
            return halt
        run.handshake("q", True)
        run.move("linear", pick, f"{where} place at Q", True, True)
        halt = _still_held(run)  # the box dropped on the way (during the retreat): it stays counted as on the pallet
        if halt:
            return halt
        run.counters = done if last else todo[i + 1].key
        halt = run.release()
        if halt:
            return halt
        # out of Q first, then the pallet: a pallet-side fault never holds the arm in the infeed's zone
        run.move("linear", above, f"{where} lift from Q", True, last)
        run.handshake("q", False)
        halt = None if last else run.wait("pallet_present")
        if halt:
            return halt
    return None


def _still_held(run) -> str | None:
    """Before the release (stacking at the target, unstacking at Q): the gripper's sensor still says it holds the item
    (a box lost on the way must not be counted as placed, or as taken to Q): the stop's message if it does not."""
    if run.case.lost and run.gripped:
        return lost_message(run.pallet, message_limit(run.cell))
    return None


def _release_and_back_out(run, retreat, key, after, where: str):
    """Release the item: the counters marked first (the layer negative: a stop before the sensor confirms leaves the
    question whether the item is down to the next start), moved on once the release is confirmed; back out along
    the retreat: (the halt, None) or (None, the height the empty gripper ends at: the entry's, clear of the stack's
    top)."""
    halt = _still_held(run)
    if halt:
        return halt, None
    run.counters = (-key[0], key[1])
    halt = run.release()
    if halt:
        return halt, None
    run.counters = after
    for pose, name, slow, exact in retreat:
        run.move("linear", pose, f"{where} {name}", slow, exact)
    return None, retreat[-1][0][2, 3]
