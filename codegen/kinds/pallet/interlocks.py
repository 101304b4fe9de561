"""A pallet's [pallet.io]: the cell's inputs the program waits for (box at Q, Q clear, pallet in place, sheet ready),
the PLC's counter reset and its handshake output, the handshakes at Q and at the sheet dispenser, program selection,
the PLC registers of the counters."""

from __future__ import annotations

from dataclasses import dataclass, field

from codegen.controllers import get_target
from codegen.kinds.pallet.keys import IO
from codegen.model.loader import build

TIMEOUT_S = IO.default("timeout_s")  # how long the program waits for an interlock before it stops with a message

# What each interlock input says when it is on (the program waits for it), and the operator's message when it does
# not come on in time
WAITS = {
    "part_present": "a box at the pick place",
    "place_clear": "the pick place clear",
    "pallet_present": "a pallet in place",
    "sheet_ready": "a slip sheet ready",
}
MISSED = {
    "part_present": "no box at the pick place",
    "place_clear": "the pick place is not clear",
    "pallet_present": "no pallet in place",
    "sheet_ready": "no slip sheet ready",
}

# The waits on the line's supply and discharge (a box at Q, a sheet ready, Q clear): a gap there is no fault, so after
# timeout_s the program says so once and waits on; the others (the pallet in place) stop with the message
WAITS_ON = ("part_present", "sheet_ready", "place_clear")


# The handshakes where the line feeds the arm (outputs, each on every target or on none): per place, the output on
# while the arm is in its zone and the one on once the arm took (put down) an item there and left the zone
HANDSHAKES = {"q": ("q_zone", "q_done"), "sheet": ("sheet_zone", "sheet_taken")}


@dataclass(frozen=True)
class PalletIO:
    """Per target, the input (its number or configured name) that is on when: a box lies at Q ready to be picked
    (stacking), Q is clear to put a box down (unstacking), the pallet stands in place, a slip sheet is ready at the
    sheet stack; reset: the PLC asks for the counters of a swapped pallet to start again (honoured only on a full
    or empty pallet, and only once the PLC drops it in answer: a reset input left on never starts a pallet again);
    done: the output that is on while the pallet is full (empty), the PLC's cue to swap it, turned off to answer a
    reset; select: the PLC asks for this pallet's program (a controller whose pallet programs share one
    task, several pallets); registers: the first of the PLC's two integer registers that hold the counters (a
    controller that keeps them in the PLC); q_zone, q_done, sheet_zone, sheet_taken: the handshake outputs at Q and
    at the sheet dispenser (HANDSHAKES). Every wait lasts at most timeout_s, then the program stops with a
    message."""

    part_present: dict = field(default_factory=dict)
    place_clear: dict = field(default_factory=dict)
    pallet_present: dict = field(default_factory=dict)
    sheet_ready: dict = field(default_factory=dict)
    reset: dict = field(default_factory=dict)
    done: dict = field(default_factory=dict)
    select: dict = field(default_factory=dict)
    # the handshakes at Q and at the slip-sheet dispenser (outputs): the arm in the zone, the pick (place) done
    q_zone: dict = field(default_factory=dict)
    q_done: dict = field(default_factory=dict)
    sheet_zone: dict = field(default_factory=dict)
    sheet_taken: dict = field(default_factory=dict)
    registers: dict = field(default_factory=dict)
    timeout_s: float = TIMEOUT_S

    def handshake(self, place: str) -> tuple[dict, dict]:
        """The zone and done outputs of a place ("q" or "sheet"; empty dicts: the cell gives none there)."""
        zone, done = HANDSHAKES[place]
        return getattr(self, zone), getattr(self, done)

    def inputs(self) -> dict[str, dict]:
        """The interlocks the program waits for: name -> (target -> signal), those the cell gives."""
        return {name: getattr(self, name) for name in WAITS if getattr(self, name)}


def parse_io(ctx, values: dict, where: str, targets, mode: str, sheets: bool) -> PalletIO:
    """[pallet.io] of one pallet, as its declaration (keys.py IO) read it: pallet_present, and part_present (stacking)
    or place_clear (unstacking), are required; sheet_ready when the pallet places slip sheets; reset optional; select
    and registers per target."""
    need, refuse = ("part_present", "place_clear") if mode == "stack" else ("place_clear", "part_present")
    if values[refuse]:
        ctx.fail(f"{where}.{refuse}", f"not an input of a {mode}ing pallet: it waits for {WAITS[need]} ({need})")
    if values["sheet_ready"] and not sheets:
        ctx.fail(f"{where}.sheet_ready", "the pallet places no slip sheets (slip_sheet.pick)")
    for key in (need, *(["sheet_ready"] if sheets else [])):
        if not values[key]:
            ctx.fail(f"{where}.{key}", f"missing: {IO[key].doc}")
    for target in values["registers"] or {}:
        if target not in targets:
            ctx.fail(f"{where}.registers.{target}", f"not one of the cell's targets ({', '.join(targets)})")
    for place, (zone, done) in HANDSHAKES.items():
        if place == "sheet" and values[zone] and not sheets:
            ctx.fail(f"{where}.{zone}", "the pallet places no slip sheets (slip_sheet.pick)")
        for given, wanted in ((zone, done), (done, zone)):
            if values[given] and not values[wanted]:
                ctx.fail(f"{where}.{wanted}", f"missing: {given} and {wanted} are one handshake, given together")
    for target in values["reset"]:
        if target not in values["done"]:
            ctx.fail(
                f"{where}.done.{target}" if values["done"] else f"{where}.done",
                f"missing: the output the {target} program turns off to answer the reset (on while the pallet is "
                f"{'full' if mode == 'stack' else 'empty'}); a reset without it could start a pallet not yet swapped",
            )
    return build(PalletIO, values)


def _facts(target: str) -> dict:
    return get_target(target).kind_tables.get("pallet", {})


# signals several pallets may share (one line's Q and its handshake, one PLC's reset); select and done not
SHARED_JOBS = (*WAITS, "reset", *(key for pair in HANDSHAKES.values() for key in pair))


def check_one_job_each(ctx, pallets, cell_io) -> None:
    """Each signal of a target does one job: the gripper's output is no pallet's done output, a box at Q is not the
    pallet in place, and no two pallets share a select input or a done output (the PLC or the program could not
    tell them apart: a gripper closing would say "pallet full", a box arriving would say "pallet in place")."""
    for target in cell_io.output if cell_io is not None else ():
        outputs = [("cell.io.output", "gripper", cell_io.output.get(target))]
        inputs = [("cell.io.feedback", "feedback", cell_io.feedback.get(target))]
        for i, pallet in enumerate(pallets):
            outputs.append((f"pallet[{i}].io.done", "done", pallet.io.done.get(target)))
            outputs += [
                (f"pallet[{i}].io.{key}", key, getattr(pallet.io, key).get(target))
                for pair in HANDSHAKES.values()
                for key in pair
            ]
            inputs += [
                (f"pallet[{i}].io.{job}", job, getattr(pallet.io, job).get(target))
                for job in (*WAITS, "reset", "select")
            ]
        for kind, jobs in (("output", outputs), ("input", inputs)):
            seen: dict = {}
            for path, job, signal in jobs:
                if signal is None:
                    continue
                key = signal.lower() if isinstance(signal, str) else signal
                if key in seen and (seen[key][1] != job or job not in SHARED_JOBS):
                    ctx.fail(
                        f"{path}.{target}",
                        f"{target} {kind} {signal!r} is {seen[key][0]}.{target} too: one signal, one job (the program "
                        "and the PLC could not tell the two apart)",
                    )
                seen.setdefault(key, (path, job))


def check_pallets_io(ctx, pallets, targets) -> None:
    """Across the pallets of a cell: a program selection input per pallet where the programs share one task and the
    cell has several pallets, and no two pallets' counters in one register."""
    shared = [t for t in targets if _facts(t).get("task")]
    if len(pallets) > 1:
        for i, pallet in enumerate(pallets):
            for target in shared:
                if target not in pallet.io.select:
                    ctx.fail(
                        f"pallet[{i}].io.select.{target}",
                        f"missing: the {target} pallet programs run in one task, which starts the one whose select "
                        "input is on",
                    )
    for target in targets:
        if "registers" not in _facts(target):
            continue
        used: dict[int, int] = {}
        for i, pallet in enumerate(pallets):
            first = counter_register(pallet, i, target)
            for register in (first, first + 1):
                if register in used:
                    ctx.fail(
                        f"pallet[{i}].io.registers.{target}",
                        f"register {register} holds pallet[{used[register]}]'s counters too",
                    )
                used[register] = i
            if first + 1 > _facts(target)["registers_max"]:
                ctx.fail(
                    f"pallet[{i}].io.registers.{target}",
                    f"pallet {i + 1}'s counters would need registers {first} and {first + 1}, beyond "
                    f"{_facts(target)['registers_max']}: give registers = {{ {target} = n }}",
                )


def counter_register(pallet, index: int, target: str) -> int:
    """The first of the PLC registers of a pallet's counters: the cell's, or the target's first + 2 per pallet."""
    given = pallet.io.registers.get(target)
    return given if given is not None else _facts(target)["registers"] + 2 * index
