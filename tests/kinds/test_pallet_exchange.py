"""A done pallet's swap: the program waits above Q for the PLC's reset, answers it, waits for the drop, then works the
new pallet; each change that breaks one of those fails verify (the reference models the swaps, the simulated PLC
codegen/kinds/pallet/exchange.py PalletExchange answers and logs where the arm stood)."""

import re
from pathlib import Path

import numpy as np
import pytest
from support.programs import sources
from test_pallet_programs import mutant_mismatches

from codegen.kinds.pallet.cases import verify_cases
from codegen.kinds.pallet.cycle import PalletCase, above_pick, done_counters, items
from codegen.kinds.pallet.messages import full_message, message_limit
from codegen.kinds.pallet.restart import expected
from codegen.kinds.pallet.section import pallets_of
from codegen.model.cell import load_cell
from codegen.render import render

PALLETS = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "pallets"
WAITED = "the program did not wait above Q for the done pallet's swap"


@pytest.fixture(scope="module")
def testmat():
    return load_cell(PALLETS / "testmat_pallet.toml")


# (what breaks, target, file, old, new, the first case that fails, what its mismatch says)
MUTATIONS = [
    (
        "waits on the pallet, before the moves above Q",
        "dtrans",
        "pal_testmat.prg",
        "    MovJ high\n    MovL PAL_ABOVE\n    Call pal_swap()\n",
        "    Call pal_swap()\n    MovJ high\n    MovL PAL_ABOVE\n",
        "full_stack",
        "moves, expected",
    ),
    (
        "goes on without the swap",
        "dtrans",
        "pal_testmat.prg",
        "  While DIn(5) <> True\n    Sleep 0.05\n  EndWhile\n",
        "",
        "full_stack",
        "step limit",
    ),
    (
        "the counters not set to the new pallet's first box",
        "dtrans",
        "pal_testmat.prg",
        "  pal_layer = 1\n  pal_box = 1\nEndSub\n",
        "EndSub\n",
        "pallet_exchanged",
        WAITED,
    ),
    (
        "the reset not answered (the done output left on)",
        "dtrans",
        "pal_testmat.prg",
        "  SetDO 3, False\n  Int resets = 0\n",
        "  Int resets = 0\n",
        "pallet_exchanged",
        "",
    ),
    (
        "the reset's drop not waited for (a reset kept on starts the new pallet)",
        "dtrans",
        "pal_testmat.prg",
        "  While DIn(5) == True\n    If resets",
        "  While False\n    If resets",
        "exchange_reset_held",
        "",
    ),
    (
        "gives up at its own timeout (a swap is no fault)",
        "dtrans",
        "pal_testmat.prg",
        "  While DIn(5) <> True\n    Sleep 0.05\n  EndWhile\n",
        "  Call pal_wait(5)\n  If DIn(5) <> True Then\n    Halt\n  EndIf\n",
        "full_stack",
        WAITED,
    ),
    (
        "the counters not set to the new pallet's first box",
        "kuka",
        "pal_testmat.src",
        "      PAL_TESTMAT_LAYER = 1\n      PAL_TESTMAT_BOX = 1\n      UP = FALSE\n",
        "      UP = FALSE\n",
        "pallet_exchanged",
        WAITED,
    ),
    (
        "waits before the move above Q",
        "abb",
        "pal_testmat.mod",
        "        MoveL stack_above_q, stack_travel, fine, stack_tool;\n        stack_swap;\n",
        "        stack_swap;\n        MoveL stack_above_q, stack_travel, fine, stack_tool;\n",
        "full_stack",
        "moves, expected",
    ),
    (
        "gives up at its own timeout",
        "ur",
        "pal_testmat.script",
        '    pal_wait_on(4, "pallet testmat is full',
        '    pal_wait(4, "pallet testmat is full',
        "full_stack",
        WAITED,
    ),
]


@pytest.mark.parametrize(
    ("what", "target", "name", "old", "new", "case", "says"), MUTATIONS, ids=[f"{m[1]}: {m[0]}" for m in MUTATIONS]
)
def test_a_broken_swap_fails_verify(testmat, what, target, name, old, new, case, says):
    found = mutant_mismatches(testmat, target, name, old, new)
    assert found and found[0].startswith(case) and says in found[0], found


def test_the_reference_works_a_new_pallet_after_each_swap(testmat):
    """After the last box: above Q, the done output on, the swap (done off), the whole pallet again, then the wait."""
    pallet = pallets_of(testmat)[0]
    keys = [item.key for item in items(pallet)]
    once = expected(testmat, pallet, PalletCase("pallet_exchanged", *keys[-1], exchanges=1))
    none = expected(testmat, pallet, PalletCase("pallet_exchanged", *keys[-1]))
    assert none.waits and none.exchanged == () and none.halt is None
    assert once.waits and once.exchanged == (len(none.moves),) and once.counters == done_counters(pallet)
    assert none.moves[-1].name == "off the pallet: above Q" and none.moves[-1].exact
    boxes = [m for m in once.moves if m.name.endswith("target")]
    assert len(boxes) == 1 + len(keys)  # the last box of the done pallet, then every box of the new one
    done = [(value, after) for what, value, after in once.outputs if what == "done"]
    assert done[-3:] == [(True, len(none.moves)), (False, len(none.moves)), (True, len(once.moves))]
    held = expected(testmat, pallet, PalletCase("exchange_reset_held", *keys[-1], exchanges=1, exchange_held=True))
    assert not held.waits and held.halt is not None and "did not go off" in held.halt
    assert held.counters == done_counters(pallet)


def test_every_target_with_a_reset_has_the_swap_cases(testmat):
    for target in testmat.targets:
        source = sources(testmat, target, "pallet")[0]
        names = {c.category for c in verify_cases(testmat, source, 0)}
        assert {"pallet_exchanged", "exchange_reset_held"} <= names, (target, names)


def _text(cell, target: str, name: str) -> str:
    (text,) = [f.text for f in render(cell, [target]) if f.relpath.endswith("/" + name)]
    return text


def test_the_kuka_swap_message_is_a_state_message_deleted_once_the_reset_comes(testmat):
    """On the text (verify's interpreter does not model what the message window shows): the wait for the swap shows a
    #STATE message and deletes that same message with Clear_KrlMsg once the reset is on (KUKA, "Programming
    user-defined messages": status messages are cleared by the program), before the answer."""
    text = _text(testmat, "kuka", "pal_testmat.src")
    swap = text[text.index("DEFFCT BOOL PAL_SWAP()") : text.index("ENDFCT", text.index("DEFFCT BOOL PAL_SWAP()"))]
    handle = re.search(r"(\w+) = SET_KRLMSG\(#STATE,", swap)
    assert handle, swap
    wait, clear = swap.index("WHILE NOT $IN[21]"), swap.index(f"CLEAR_KRLMSG({handle.group(1)})")
    assert wait < clear < swap.index("$OUT[22] = FALSE"), swap


def test_the_abb_swap_message_is_written_on_a_cleared_display(testmat):
    """On the text: once the wait for the swap lasted its timeout, TPErase before the swap's one message (RAPID
    Summary, communicating using the teach pendant: TPErase clears the operator display), so the display shows that
    state, not the messages before it."""
    text = _text(testmat, "abb", "pal_testmat.mod")
    swap = text[text.index("LOCAL PROC stack_swap()") : text.index("ENDPROC", text.index("LOCAL PROC stack_swap()"))]
    late = swap.index("IF late THEN")
    assert swap.index("WaitDI diPalletReset, 1 ") < late < swap.index("TPErase;") < swap.index("TPWrite "), swap
    assert swap.count("TPWrite ") == 1, swap


def test_the_kuka_waits_on_the_supply_leave_no_message_behind(testmat):
    """On the text: a wait on the supply that lasts its timeout shows a #STATE message and deletes it once the input
    comes (Clear_KrlMsg), so a shift's gaps do not pile notifications up in the message window."""
    text = _text(testmat, "kuka", "pal_testmat.src")
    start = text.index("DEFFCT BOOL PAL_PART()")
    wait = text[start : text.index("ENDFCT", start)]
    assert "SET_KRLMSG(#NOTIFY" not in wait, wait
    handle = re.search(r"(\w+) = SET_KRLMSG\(#STATE,", wait)
    assert handle and wait.index("ENDWHILE") < wait.index(f"CLEAR_KRLMSG({handle.group(1)})"), wait


@pytest.mark.parametrize(
    ("old", "new", "case"),
    [
        # the empty pallet swapped, the counters left at 0/0: the program ends instead of working the new one
        ("      pal_swap()\n      pal_layer = 5\n      pal_box = 6\n", "      pal_swap()\n", "pallet_exchanged"),
        # the last box held at the start and put down at Q: the empty pallet's swap not waited for
        (
            "  if pal_layer < 1:   # the pallet empty",
            "  if pal_layer < 1 and not pal_up:   # the pallet empty",
            "held_at_start pallet testmat layer 0 box 0",
        ),
        # empty at the start, the reset off: the stop kept
        (
            "    end   # no reset yet: the swap waited for above Q below, as at a pallet's end\n",
            '    else:\n      pal_stop("empty")\n    end\n',
            "pallet_empty pallet testmat layer 0 box 0",
        ),
    ],
)
def test_an_unstacking_program_waits_for_the_empty_pallets_swap(unstacking, old, new, case):
    found = mutant_mismatches(unstacking, "ur", "pal_testmat.script", old, new)
    assert found and found[0].startswith(case) and WAITED in found[0], found


def test_an_unstacking_program_empty_at_the_start_waits_above_q(unstacking):
    """Empty at the start: the swap waited for at home instead of above Q fails verify (its moves)."""
    old = (
        "    if not pal_up:\n      movej(get_inverse_kin(PAL_ABOVE, qnear=PAL_ABOVE_QNEAR), a=1.2, v=0.25)\n"
        "    end\n    pal_swap()\n"
    )
    found = mutant_mismatches(unstacking, "ur", "pal_testmat.script", old, "    pal_swap()\n")
    assert found and found[0].startswith("pallet_empty pallet testmat layer 0 box 0"), found


# A pallet done at the start (the reset off): a program that stops, or works the done pallet, or waits elsewhere than
# above Q fails verify on every target. (target, file, old, new, what its first mismatch says)
AT_START = [
    ("dtrans", "pal_testmat.prg", "  ElseIf held == 1 Then\n", "  Else\n", WAITED),
    (
        "dtrans",
        "pal_testmat.prg",
        "  MovJ PAL_ABOVE\n  Call pal_swap()\nEndIf\nWhile",
        "  pal_layer = 1\n  pal_box = 1\nEndIf\nWhile",
        "moves, expected 1",
    ),
    (
        "dtrans",
        "pal_testmat.prg",
        "  MovJ PAL_ABOVE\n  Call pal_swap()\nEndIf\nWhile",
        "  Call pal_swap()\nEndIf\nWhile",
        "",
    ),
    ("ur", "pal_testmat.script", "    elif pal_held:   # a box", "    else:   # a box", WAITED),
    (
        "ur",
        "pal_testmat.script",
        "    movej(get_inverse_kin(PAL_ABOVE, qnear=PAL_ABOVE_QNEAR), a=1.2, v=0.25)\n"
        "    pal_swap()\n    pal_layer = 1",
        "    pal_layer = 1",
        "moves, expected 2",
    ),
    ("kuka", "pal_testmat.src", "      IF HELD THEN ; a box", "      IF TRUE THEN ; a box", WAITED),
    (
        "kuka",
        "pal_testmat.src",
        "    PTP PAL_ABOVE_AXES\n    IF NOT PAL_SWAP() THEN\n      RETURN\n    ENDIF\n    PAL_TESTMAT_LAYER = 1",
        "    PAL_TESTMAT_LAYER = 1",
        "moves, expected 2",
    ),
    ("abb", "pal_testmat.mod", "      ELSEIF held THEN\n", "      ELSE\n", WAITED),
    (
        "abb",
        "pal_testmat.mod",
        "      MoveAbsJ stack_above_q_axes\\NoEOffs, stack_travel, fine, stack_tool;\n      stack_swap;\n    ENDIF\n",
        "      stack_swap;\n    ENDIF\n",
        "moves, expected 2",
    ),
]


@pytest.mark.parametrize(
    ("target", "name", "old", "new", "says"), AT_START, ids=[f"{m[0]}-{i}" for i, m in enumerate(AT_START)]
)
def test_a_start_on_a_done_pallet_that_does_not_wait_for_the_swap_fails_verify(testmat, target, name, old, new, says):
    found = mutant_mismatches(testmat, target, name, old, new)
    assert found and found[0].startswith("pallet_full pallet testmat layer 6 box 1") and says in found[0], found


def test_the_reference_waits_above_q_for_the_swap_of_a_pallet_done_at_the_start(testmat, tmp_path):
    """Full at the start, the reset off: home, above Q (stopping there), the done output on, the swap, the new pallet;
    a box in the gripper then, or a cell without a reset: the stop."""
    pallet = pallets_of(testmat)[0]
    done, keys = done_counters(pallet), [item.key for item in items(pallet)]
    waiting = expected(testmat, pallet, PalletCase("pallet_full", *done))
    assert waiting.halt is None and waiting.waits and waiting.exchanged == () and waiting.counters == done
    (above,) = waiting.moves
    assert above.kind == "joint" and above.exact and np.allclose(above.tcp2base, above_pick(pallet))
    assert [o for o in waiting.outputs if o[0] == "done"] == [("done", True, 0), ("done", True, 1)]
    swapped = expected(testmat, pallet, PalletCase("swapped_at_start", *done, exchanges=1))
    assert swapped.waits and swapped.exchanged == (1,) and swapped.counters == done
    assert sum(1 for m in swapped.moves if m.name.endswith("target")) == len(keys)
    message = full_message(pallet, message_limit(testmat))
    held = expected(testmat, pallet, PalletCase("held_at_start", *done, closed=True))
    assert held.halt == message and held.moves == () and not held.waits
    text = (PALLETS / "testmat_pallet.toml").read_text()
    reset = next(line for line in text.splitlines() if line.startswith("reset = "))
    (tmp_path / "testmat_pallet.toml").write_text(text.replace(reset + "\n", ""))
    bare = load_cell(tmp_path / "testmat_pallet.toml")
    stops = expected(bare, pallets_of(bare)[0], PalletCase("pallet_full", *done))
    assert (
        stops.halt == full_message(pallets_of(bare)[0], message_limit(bare)) and stops.moves == () and not stops.waits
    )


def test_every_target_with_a_reset_has_the_start_swap_cases(testmat):
    for target in testmat.targets:
        source = sources(testmat, target, "pallet")[0]
        cases = [c.data.case for c in verify_cases(testmat, source, 0)]
        assert any(c.category == "swapped_at_start" and c.exchanges == 1 and not c.exchange_held for c in cases)
        assert any(c.category == "swapped_at_start" and c.exchange_held for c in cases), target


def test_a_stop_in_a_release_is_named_by_its_box_and_the_marked_counters():
    """The report names a case by its item: the layer counted from 1 as everywhere else, the counters' mark (the
    layer negative, as the program leaves a stop in a release) said apart."""
    from codegen.kinds.pallet.verify import VerifyPart

    cell = load_cell(PALLETS / "testmat_pallet.toml")
    source = sources(cell, "kuka", "pallet")[0]
    cases = [c for c in verify_cases(cell, source, 0) if c.category == "stopped_in_release"]
    assert cases
    for case in cases:
        layer, box = case.data.case.layer, case.data.case.box
        assert layer < 0
        shown = VerifyPart(None).describe(cell, case)
        assert shown.endswith(f"layer {-layer} box {box} (the counters marked: layer {layer})"), shown
        assert f"layer {layer} box" not in shown
