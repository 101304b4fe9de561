"""A pallet program's start as its reference: held item, full pallet, reset, answers; then the cycle from there."""

from __future__ import annotations

from dataclasses import replace

from codegen.kinds.pallet.cycle import (
    Expected,
    PalletCase,
    Run,
    above_pick,
    done_counters,
    items,
    stacking,
    unstacking,
)
from codegen.kinds.pallet.messages import (
    base_message,
    counters_message,
    empty_message,
    foreign_message,
    full_message,
    known_message,
    message_limit,
    released_message,
    reset_held_message,
)
from codegen.kinds.pallet.section import Pallet

YES, NO = "Yes", "No"  # the operator's answers to the question after a stop during a release (softkeys 1 and 2)


def expected(cell, pallet: Pallet, case: PalletCase) -> Expected:
    """What the pallet's program does in this case: the done output set from the counters, the checks before any
    move (a full or empty pallet, reset by the PLC through the handshake or not; counters outside the stack), then
    each item from the counters, and the done output on once the pallet is done. A pallet done at the start with the
    PLC's reset off: where the cell gives a reset, the arm goes from home above Q and waits there for the swap as at
    a pallet's end (an item held then: the stop); without one, the stop. A box held at the start (a cycle
    stopped on the way) is finished: stacking, it is the item the counters name (they move only after a confirmed
    release), carried from home onto its place; unstacking, it left the pallet (the counters moved at the grip), and
    is put down at Q first, even when it was the last box."""
    start, done = (case.layer, case.box), done_counters(pallet)
    limit = message_limit(cell)
    keys = [item.key for item in items(pallet)]
    put_down = case.closed and pallet.mode == "unstack"
    if case.base_off:  # the pallet frame read from a base not measured: the stop before any output or move
        return Expected((), (), base_message(pallet, pallet.base_data, limit), start, start, holds=case.closed)
    if case.closed and case.foreign:  # not this program's item: it stops before anything else
        return Expected((), (), foreign_message(pallet, limit), start, start)
    # a held item: the gripper's output set to grip again first (a stop, or a release that did not finish, may have
    # left it off while the item is still in the gripper)
    said = [("gripper", cell.io.value, 0)] if case.closed else []
    known_asked = False
    if case.unknown:  # the counters are the store's file's: no item before the pallet is known to be new
        if (case.reset or case.reset_asked) and pallet.io.reset:  # the PLC's handshake: the done output off, the
            known_asked = case.reset_asked  # reset dropped (on while the question was shown: that ended it)
            said.append(("done", False, 0))
            if case.reset_held:
                message = reset_held_message(pallet, limit)
                return Expected((), tuple(said), message, start, start, holds=case.closed, known=False)
        else:  # the operator asked (a store with the flag is a target's that asks): Yes, a new pallet; No, or none
            known_asked = True
            if case.answer != YES:
                out = Expected((), tuple(said), known_message(pallet, limit), start, start, holds=case.closed)
                return replace(out, known=False, known_asked=known_asked)
        start = keys[0]
    asked, swap_first = False, False
    if pallet.mode == "unstack" and start[0] < 0:  # a stop between the grip and Q (the counters marked)
        start = (-start[0], start[1])
        if start in keys:
            following = keys.index(start) + 1
            after = keys[following] if following < len(keys) else done
            if case.closed:  # the box gripped is still in the gripper: it left the pallet, put down at Q below
                start = after
            else:  # the gripper empty: only the operator can tell whether the box is back in its place
                if case.answer is None:
                    marked = (-start[0], start[1])
                    return Expected((), (), released_message(pallet, limit), marked, start, holds=False)
                asked = True
                if case.answer == NO:  # not on the pallet: the counters move on as after a box put down at Q
                    start = after
    if pallet.mode == "stack" and start[0] < 0:  # a stop came during a release: is the item down?
        start = (-start[0], start[1])
        if start in keys and not case.closed:  # the gripper holds nothing: only the operator can tell
            if case.answer is None:
                return Expected((), (), released_message(pallet, limit), (-start[0], start[1]), start, holds=False)
            # (the gripper empty: no output set before the question)
            asked = True
            if case.answer == YES:  # down: the counters move on as after a confirmed release
                following = keys.index(start) + 1
                start = keys[following] if following < len(keys) else done
    # then the PLC's full (empty) output, from the counters
    said.append(("done", start == done, 0))
    if start == done and not put_down:
        if case.reset and pallet.io.reset:  # the handshake: the done output off answers the PLC, which drops reset
            said.append(("done", False, 0))
            if case.reset_held:  # the reset stays on: no swap confirmed, the counters stay
                said.append(("done", True, 0))
                return Expected((), tuple(said), reset_held_message(pallet, limit), start, start, holds=case.closed)
            start = keys[0]
        elif pallet.io.reset and not case.closed:  # no reset yet: the swap waited for above Q, as at a pallet's end
            swap_first = True
        else:
            message = full_message(pallet, limit) if pallet.mode == "stack" else empty_message(pallet, limit)
            return Expected((), tuple(said), message, start, start, asked=asked, holds=case.closed)
    if start not in keys and start != done:
        return Expected((), tuple(said), counters_message(pallet, limit), start, start, asked=asked, holds=case.closed)
    run = Run(cell, pallet, case, start)
    todo = [item for item in items(pallet)][keys.index(start) :] if start in keys else []
    run.outputs = [*said, *run.outputs]
    if case.closed:  # no release at the start: the gripper holds the item
        run.outputs = said
        run.carrying = put_down or todo[0].placement is not None
        run.sheet = not run.carrying
    run.zones_off()
    if swap_first:  # done at the start: from home above Q, where the done pallet's swap is waited for
        run.move("joint", above_pick(pallet), "done at the start: above Q", False, True)
        halt = None
    elif put_down:
        halt = _put_down(run)
        halt = halt or (unstacking(run, todo, done, from_q=True) if todo else None)
    else:
        halt = (stacking if pallet.mode == "stack" else unstacking)(run, todo, done)
    exchanged, waits = (), False
    if halt is None:  # the pallet is done: the PLC's cue to swap it
        run.outputs.append(("done", True, len(run.moves)))
        halt, exchanged, waits = _exchanges(run, done)
    out = replace(run.result(halt, start), asked=asked, known_asked=known_asked)
    return replace(out, exchanged=exchanged, waits=waits)


def _exchanges(run: Run, done: tuple[int, int]) -> tuple[str | None, tuple[int, ...], bool]:
    """Where the PLC resets the counters: the program waits above Q (where the pallet's last item left the arm) for
    the swap's reset, answers it (the done output off), waits until the PLC drops it (a reset kept on: the done output
    on again and the stop, the counters kept), then works the new pallet from its first item; after the case's swaps
    the run ends with the program waiting. (the stop or None, the moves commanded at each swap, whether it waits)."""
    pallet = run.pallet
    if not pallet.io.reset:  # no swap signal: the program ends, the operator sets the counters
        return None, (), False
    exchanged = []
    for _ in range(run.case.exchanges):
        exchanged.append(len(run.moves))
        run.outputs.append(("done", False, len(run.moves)))
        if run.case.exchange_held:
            run.outputs.append(("done", True, len(run.moves)))
            return reset_held_message(pallet, message_limit(run.cell)), tuple(exchanged), False
        todo = items(pallet)
        run.counters = todo[0].key
        halt = stacking(run, todo, done) if pallet.mode == "stack" else unstacking(run, todo, done, from_q=True)
        if halt:
            return halt, tuple(exchanged), False
        run.outputs.append(("done", True, len(run.moves)))
    return None, tuple(exchanged), True


def _put_down(run: Run) -> str | None:
    """Unstacking, a box held at the start: above Q (joint), Q clear waited for, Q (slow, exact), release, above Q
    (slow, exact)."""
    pallet = run.pallet
    above = above_pick(pallet)
    run.move("joint", above, "held box above Q", False, False)
    run.arrive("q")
    halt = run.wait("place_clear")
    if halt:
        return halt
    run.handshake("q", True)
    run.move("linear", pallet.pick.matrix(), "held box place at Q", True, True)
    halt = run.release()
    if halt:
        return halt
    run.move("linear", above, "held box lift from Q", True, True)
    run.handshake("q", False)
    return None
