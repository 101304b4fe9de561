"""The operator messages of a pallet program: each within the shortest string of the cell's controllers, the pallet's
name shortened where it would not fit, never the instruction."""

from __future__ import annotations

from codegen.controllers import get_target
from codegen.kinds.pallet.interlocks import MISSED, WAITS_ON
from codegen.kinds.pallet.section import Pallet
from codegen.kinds.pallet.stack import placements

ELLIPSIS = "..."


def message_limit(cell) -> int:
    """The characters an operator message may have in every program of the cell: the shortest string of its targets
    (targets/<t>.toml string_max: 80 where a message text or a string holds 80), so each program shows the same text."""
    return min(get_target(name).string_max for name in cell.targets)


def _named(pattern: str, pallet: Pallet, limit: int) -> str:
    """The message with the pallet's name; a name that would make it longer than `limit` shortened to its start and
    "..." (the emitter would cut the end: what the operator must do)."""
    text = pattern.format(name=pallet.name)
    if len(text) <= limit:
        return text
    room = max(0, limit - len(pattern.format(name="")) - len(ELLIPSIS))
    return pattern.format(name=pallet.name[:room] + ELLIPSIS)


def _top_count(pallet: Pallet) -> int:
    return sum(1 for p in placements(pallet) if p.layer == pallet.layers)


def full_message(pallet: Pallet, limit: int) -> str:
    then = "reset its counters from the PLC" if pallet.io.reset else "set layer 1 and box 1"
    return _named(f"pallet {{name}} is full: swap it, then {then}", pallet, limit)


def empty_message(pallet: Pallet, limit: int) -> str:
    if pallet.io.reset:
        return _named("pallet {name} is empty: bring a full one, then reset its counters from the PLC", pallet, limit)
    pattern = f"pallet {{name}} is empty: bring a full one, set layer {pallet.layers} box {_top_count(pallet)}"
    return _named(pattern, pallet, limit)


def counters_message(pallet: Pallet, limit: int) -> str:
    return _named("pallet {name}: layer or box counter out of range", pallet, limit)


def wait_message(pallet: Pallet, interlock: str, limit: int, held: str | None = None) -> str:
    """The stop after an interlock input stayed off for the timeout, with what the gripper holds meanwhile (held: "box"
    or "sheet"; unstacking at Q: the box)."""
    held = held or ("box" if interlock == "place_clear" else None)
    then = f", the {held} is in the gripper" if held else ""  # a ";" is not a safe character (codegen/emit.py)
    return _named(f"pallet {{name}}: {MISSED[interlock]} in {pallet.io.timeout_s:g} s{then}", pallet, limit)


def still_waiting_message(pallet: Pallet, interlock: str, limit: int) -> str:
    """The notification after a wait on the supply or discharge (interlocks.WAITS_ON) lasted the timeout: the program
    waits on."""
    return _named(f"pallet {{name}}: {MISSED[interlock]} for {pallet.io.timeout_s:g} s, still waiting", pallet, limit)


def reset_held_message(pallet: Pallet, limit: int) -> str:
    """The stop when the PLC keeps its reset on after the program answered it (the done output off): a reset input
    left on (a level, not a request) never starts a pallet again; the counters stay as they were."""
    pattern = f"pallet {{name}}: the PLC's reset did not go off in {pallet.io.timeout_s:g} s, counters kept"
    return _named(pattern, pallet, limit)


def released_question(pallet: Pallet, limit: int) -> str:
    """The operator's question at the start with the counters marked and the gripper empty. Stacking, after a stop
    during a release: Yes, the item is down, the counters move on; No, it is placed again. Unstacking, after a stop
    between the grip and Q (the box dropped on the way, or taken out): Yes, it is back in its place on the pallet and
    taken again; No, it is not, the counters move on. The No tells the operator to remove the item first: a stacking
    program places a new one in its slot, an unstacking one goes to the next box with the dropped one maybe on it."""
    if pallet.mode == "unstack":
        return _named("pallet {name}: stopped before Q. Box back in its place? No: remove it first", pallet, limit)
    return _named("pallet {name}: stopped in a release. Is the item down? No: remove it first", pallet, limit)


def released_message(pallet: Pallet, limit: int) -> str:
    """The stop where the program cannot ask (or the question went unanswered): the counters keep their mark."""
    if pallet.mode == "unstack":
        return _named("pallet {name}: stopped on the way to Q: check the box, then set the counters", pallet, limit)
    return _named("pallet {name}: stopped in a release: check the item, then set the counters", pallet, limit)


def foreign_message(pallet: Pallet, limit: int) -> str:
    """The stop at the start when the gripper holds an item this program did not grip (another pallet's program of the
    same arm did, or the counters' store came back from its file with the flag FALSE): it is not this pallet's to
    finish."""
    return _named("pallet {name}: item held is another program's, or counters reloaded: remove it", pallet, limit)


def lost_message(pallet: Pallet, limit: int) -> str:
    """The stop at the target when the gripper's sensor no longer sees the item it gripped: lost on the way, not
    counted as placed."""
    return _named("pallet {name}: the item was lost from the gripper on the way: find it", pallet, limit)


def known_question(pallet: Pallet, limit: int) -> str:
    """The operator's question at the start when the counters' store came back from its file (its known flag FALSE):
    Yes, the pallet is new (empty for stacking, full for unstacking), its first item next; No, a stop."""
    state = "full" if pallet.mode == "unstack" else "empty"
    return _named(f"pallet {{name}}: counters reloaded from file. Is the pallet {state} (new)?", pallet, limit)


def known_message(pallet: Pallet, limit: int) -> str:
    """The stop when the operator said No or did not answer: the counters stay the file's, the flag FALSE."""
    return _named("pallet {name}: counters reloaded from file: set them, then the known flag", pallet, limit)


def base_message(pallet: Pallet, number: int, limit: int) -> str:
    """The stop at the start when the controller's numbered base is not the pallet's frame: not measured, measured
    elsewhere, or another pallet's."""
    return _named(f"pallet {{name}}: base {number} is not this pallet's frame: measure it", pallet, limit)


def select_message() -> str:
    return "no pallet program selected: the PLC sets one select input"


def all_messages(pallet: Pallet, limit: int) -> list[str]:
    return [
        full_message(pallet, limit),
        empty_message(pallet, limit),
        counters_message(pallet, limit),
        *([reset_held_message(pallet, limit)] if pallet.io.reset else []),
        known_question(pallet, limit),
        known_message(pallet, limit),
        released_question(pallet, limit),
        released_message(pallet, limit),
        *(
            still_waiting_message(pallet, name, limit) if name in WAITS_ON else wait_message(pallet, name, limit)
            for name in pallet.io.inputs()
        ),
        *(wait_message(pallet, "pallet_present", limit, held) for held in rechecked(pallet)),
    ]


def rechecked(pallet: Pallet) -> tuple[str, ...]:
    """What a stacking program carries when it asks again for the pallet before the load goes over it: a box, and a
    slip sheet where it places them (unstacking: none, it carries no load onto the pallet)."""
    if pallet.mode != "stack":
        return ()
    return ("box", "sheet") if pallet.slip_pick is not None else ("box",)
