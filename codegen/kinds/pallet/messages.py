"""The operator messages of a pallet program: each within the controller's string limit, or the cell is refused."""

from __future__ import annotations

from codegen.emit import EmitError
from codegen.kinds.pallet.interlocks import MISSED
from codegen.kinds.pallet.section import Pallet
from codegen.kinds.pallet.stack import placements


def _top_count(pallet: Pallet) -> int:
    return sum(1 for p in placements(pallet) if p.layer == pallet.layers)


def full_message(pallet: Pallet) -> str:
    then = "reset its counters from the PLC" if pallet.io.reset else "set layer 1 and box 1"
    return f"pallet {pallet.name} is full: swap it, then {then}"


def empty_message(pallet: Pallet) -> str:
    if pallet.io.reset:
        return f"pallet {pallet.name} is empty: bring a full one, then reset its counters from the PLC"
    return f"pallet {pallet.name} is empty: bring a full one, set layer {pallet.layers} box {_top_count(pallet)}"


def held_message(pallet: Pallet) -> str:
    return f"pallet {pallet.name}: a box is in the gripper (sensor on): take it out, start again"


def counters_message(pallet: Pallet) -> str:
    return f"pallet {pallet.name}: layer or box counter out of range"


def wait_message(pallet: Pallet, interlock: str) -> str:
    """The stop after an interlock input stayed off for the timeout (unstacking at Q: the box is in the gripper)."""
    held = "; the box is in the gripper" if interlock == "place_clear" else ""
    return f"pallet {pallet.name}: {MISSED[interlock]} in {pallet.io.timeout_s:g} s{held}"


def select_message() -> str:
    return "no pallet program selected: the PLC sets one select input"


def all_messages(pallet: Pallet) -> list[str]:
    return [
        full_message(pallet),
        empty_message(pallet),
        held_message(pallet),
        counters_message(pallet),
        *(wait_message(pallet, name) for name in pallet.io.inputs()),
    ]


def check_lengths(pallet: Pallet, target) -> None:
    """Every message within the target's string limit (KRL Msg_txt CHAR[80], RAPID strings 80): a longer one would
    reach the operator cut; EmitError names the pallet and the message."""
    for message in all_messages(pallet):
        if len(message) > target.string_max:
            raise EmitError(
                f"pallet {pallet.name!r}: the operator message {message!r} has {len(message)} characters, the "
                f"{target.name} controller shows {target.string_max}: give the pallet a shorter name"
            )
