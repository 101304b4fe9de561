"""verify names a failing run's fault against the expectation the run followed (of the several a case accepts), and
a case's numbers rounded for reading."""

from __future__ import annotations

import re

import pytest

from codegen.model.cell import EXAMPLES_DIR, load_cell
from codegen.verify.report import readable
from tests.support import stations

DEMO = EXAMPLES_DIR / "agv_machine_tending.toml"


@pytest.fixture(scope="module")
def cell():
    return load_cell(DEMO)


def test_a_speed_edit_is_blamed_on_its_line_in_the_case_answered_twice(cell):
    """A one-line speed edit yielded "MISMATCH vision_twice ... move 2 (approach): position error 0.707 mm": the run
    had taken the vision PC's second answer and was compared with the first answer's poses."""
    text, _ = stations.files(cell, "ur")
    lines = text.splitlines()
    at = next(i for i, line in enumerate(lines) if line.strip().startswith("movel(p1_tray_done_above"))
    assert "v=0.2500" in lines[at]
    lines[at] = lines[at].replace("v=0.2500", "v=0.2000")
    program = stations.source(cell, "ur", "\n".join(lines) + "\n")
    cases = [c for c in stations.build_cases(cell, 1, 0) if c.category == "vision_twice"][:1]
    assert cases and cases[0].reading.station_id == 1
    row = stations.verify(cell, program, cases)
    assert row.mismatches == 1
    (shown,) = row.first_mismatches
    assert f"(tray_done_above, line {at + 1}): v 0.2, expected 0.25" in shown, shown
    assert "position error" not in shown


def test_a_case_is_named_with_its_numbers_rounded_for_reading(cell):
    """The least joint margin's case read "reading (447.9360032559464, 347.2639967440536, 168.60999999999999)"."""
    assert readable("corner station 6 reading (447.9360032559464, 347.2639967440536, 168.60999999999999)") == (
        "corner station 6 reading (447.936003, 347.263997, 168.61)"
    )
    assert readable("layer 2 box 11, 0.5 mm, -0.00000001, v2.12345678") == "layer 2 box 11, 0.5 mm, 0, v2.12345678"
    text, _ = stations.files(cell, "ur")
    cases = [c for c in stations.build_cases(cell, 2, 0) if c.category == "random"][:2]
    row = stations.verify(cell, stations.source(cell, "ur", text.replace("v=0.2500", "v=0.2000")), cases)
    for shown in row.first_mismatches:
        reading = re.search(r"reading \(([^)]*)\)", shown).group(1)
        assert all(len(n.split(".")[-1]) <= 6 for n in reading.split(", ")), shown
