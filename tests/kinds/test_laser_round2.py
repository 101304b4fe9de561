"""The laser TCP program's second review: each item in the programs, a change restoring the old behaviour failing."""

from __future__ import annotations

import pytest
from support.programs import edited, first, regex_edit, verify_one

from codegen.model.cell import load_cell

CELL = "codegen/examples/laser/laser_tcp.toml"


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


# --- UR asks the operator before it writes the production tool -----------------------------------------------


def test_ur_asks_before_it_writes_and_a_program_that_writes_unasked_fails_verify(cell):
    """The operator's No leaves pin_tcp as it was (verify's confirmation_refused case); a node that writes without
    asking (the question's answer taken as Yes) is a mismatch."""
    source = first(cell, "ur", "laser")
    only = frozenset({"operator_refuses"})
    row = verify_one(cell, source, scenarios=only)
    assert (row.cases, row.mismatches) == (1, 0), row.first_mismatches
    unasked = edited(source, regex_edit(r"request_boolean_from_primary_client\([^)]*\)", "True"), "unasked")
    row = verify_one(cell, unasked, scenarios=only)
    assert row.mismatches == 1, row.first_mismatches


def test_the_ur_node_states_it_belongs_in_before_start():
    """A text test (no simulation sees where PolyScope places a node): the header says the node goes in the Before
    Start sequence, and every def and thread of the file stands at its top level (two spaces: the node's body)."""
    cell = load_cell(CELL)
    text = first(cell, "ur", "laser").files[0].text
    assert "Before Start sequence" in text
    definitions = [line for line in text.splitlines() if line.lstrip().startswith(("def ", "thread "))]
    assert definitions and all(line.startswith("  ") and not line.startswith("   ") for line in definitions)
