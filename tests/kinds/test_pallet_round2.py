"""The pallet programs' second review: the UR counters copied by the PLC only at the program's "counters written"
toggle, and the ABB tool and work-object data kept in the system module; the programs without them fail verify."""

from pathlib import Path

import pytest
from support.programs import edited, sources, verify_one

from codegen.kinds.pallet.latch import CounterLatch
from codegen.model.cell import load_cell

PALLETS = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "pallets"

WRITE = "    write_output_integer_register(0, layer)\n    write_output_integer_register(1, box)\n"
NOTE = '    # "counters written": the PLC copies the two registers at this change, never on the running bit alone\n'
TOGGLE = "    write_output_boolean_register(0, not read_output_boolean_register(0))\n"


def _mismatches(cell_file: str, target: str, name: str, old: str, new: str) -> list:
    """The first mismatches of the program whose file `name` has `old` replaced by `new` (each occurrence)."""
    cell = load_cell(PALLETS / cell_file)
    program = next(p for p in sources(cell, target, "pallet") if any(f.name.endswith(name) for f in p.files))
    (own,) = [f for f in program.files if f.name.rsplit("/", 1)[-1] == name]
    assert old in own.text, f"{old!r} not in the {target} program's {name}"
    mutant = edited(program, lambda t: t.replace(old, new) if t == own.text else t)
    return verify_one(cell, mutant, first_mismatch=True, clearance=False).first_mismatches


# (file, old, new, what the first mismatch says): the toggle taken out (the PLC copies nothing, its memory keeps the
# start's counters), the toggle flipped before the registers are written (the PLC copies the values before them)
UR_MUTATIONS = [
    ("pal_testmat.script", TOGGLE, "", "the PLC's memory holds"),
    ("pal_testmat.script", WRITE + NOTE + TOGGLE, TOGGLE + WRITE, "the PLC's memory holds"),
    ("pal_testmat_node.script", TOGGLE, "", "the PLC's memory holds"),
]


@pytest.mark.parametrize(("name", "old", "new", "says"), UR_MUTATIONS)
def test_a_ur_program_without_its_counters_written_toggle_fails_verify(name, old, new, says):
    mismatches = _mismatches("testmat_pallet.toml", "ur", name, old, new)
    assert mismatches, "the mutant passes verify"
    assert says in mismatches[0], mismatches[0]


TOOL = (
    "  LOCAL PERS tooldata stack_tool := [TRUE, [[0.0000, 0.0000, 120.0000], [1.000000000, 0.000000000, 0.000000000, "
    "0.000000000]], [0.800, [0.0000, 0.0000, 50.0000], [1.000000, 0.000000, 0.000000, 0.000000], 0.001085, 0.001085, "
    "0.000250]];\n"
)
WOBJ = (
    '  LOCAL PERS wobjdata pal_testmat_wobj := [FALSE, TRUE, "", [[650.0000, -50.0000, 50.0000], '
    "[1.000000000, 0.000000000, 0.000000000, 0.000000000]], [[0, 0, 0], [1, 0, 0, 0]]];\n"
)
HOME = "  LOCAL CONST jointtarget stack_home"

# the tool or the pallet's work object declared in the program module again (as it was before the system module
# held them): a program load would set a taught TCP or frame back
ABB_MUTATIONS = [
    (HOME, TOOL + HOME, "tooldata stack_tool is declared in pal_testmat.mod"),
    (HOME, WOBJ + HOME, "wobjdata pal_testmat_wobj is declared in pal_testmat.mod"),
]


@pytest.mark.parametrize(("old", "new", "says"), ABB_MUTATIONS)
def test_an_abb_program_declaring_its_own_tool_or_work_object_fails_verify(old, new, says):
    mismatches = _mismatches("testmat_pallet.toml", "abb", "pal_testmat.mod", old, new)
    assert mismatches, "the mutant passes verify"
    assert any(says in m for m in mismatches), mismatches


def test_the_abb_task_has_one_tool_and_a_work_object_per_pallet_in_its_system_module():
    cell = load_cell(PALLETS / "eur_pallet.toml")
    (program,) = sources(cell, "abb", "pallet")
    texts = {f.name.rsplit("/", 1)[-1]: f.text for f in program.files}
    data = texts.pop("pallet_data.sys")
    assert data.count("PERS tooldata stack_tool :=") == 1
    assert "PERS wobjdata pal_eur_wobj :=" in data and "PERS wobjdata pal_eur_in_wobj :=" in data
    for name, text in texts.items():
        assert "PERS tooldata" not in text, name
        assert "PERS wobjdata" not in text, name
    assert "\\WObj:=pal_eur_wobj" in texts["pal_eur.mod"] and "\\WObj:=pal_eur_in_wobj" in texts["pal_eur_in.mod"]


class _Machine:
    """What the PLC's block reads of a run: the program's outputs, the inputs at the start, its own state."""

    def __init__(self):
        self.outputs, self.inputs, self.device_state = {}, {}, {}


def test_the_plcs_block_copies_at_the_toggle_alone():
    """A start after a boot: the registers hold what the program has not written (0 and 0) and the running bit is on;
    the memory keeps the counters until the program flips the toggle after writing them."""
    latch = CounterLatch("output_integer_register_0", "output_integer_register_1", "output_boolean_register_0", (3, 2))
    machine = _Machine()
    latch.on_wait(machine, "start")
    assert latch.memory == (3, 2) and latch.reported == (3, 2)  # nothing written: the start's counters
    machine.outputs.update({"output_integer_register_0": 3, "output_integer_register_1": 3})
    latch.on_wait(machine, "written")
    assert latch.memory == (3, 2) and latch.reported == (3, 3)  # written, not yet said so
    machine.outputs["output_boolean_register_0"] = True
    latch.on_wait(machine, "toggled")
    assert latch.memory == (3, 3)
    machine.outputs["output_integer_register_0"] = -3
    machine.outputs["output_boolean_register_0"] = False
    latch.on_wait(machine, "marked")
    assert latch.memory == (-3, 3) and latch.reported == (-3, 3)  # a negative layer as it is
