"""The [laser] numbers a fault probe accepted although the TCP program cannot meet them, and a numbered KUKA tool."""

from __future__ import annotations

import pytest
from support.cells import EXAMPLES
from support.programs import sources, verify

from codegen.model.cell import CellError, load_cell

UR_ONLY = (
    ('targets = ["ur", "kuka", "abb"]', 'targets = ["ur"]'),
    ('kuka = "KR 10 R1100 sixx"\n', ""),
    ('abb = "IRB 1600-10/1.45"\n', ""),
    ('beam_x = { ur = 2, kuka = 21, abb = "diLaserX" }', "beam_x = { ur = 2 }"),
    ('beam_y = { ur = 3, kuka = 22, abb = "diLaserY" }', "beam_y = { ur = 3 }"),
    ('production_tool = { ur = "pin_tcp", kuka = 3, abb = "tPin" }', 'production_tool = { ur = "pin_tcp" }'),
)


def edited(tmp_path, *changes: tuple[str, str]):
    text = EXAMPLES["laser_tcp"].read_text(encoding="utf-8")
    for old, new in changes:
        assert old in text, f"{old!r} not found"
        text = text.replace(old, new, 1)
    path = tmp_path / "laser_tcp.toml"
    path.write_text(text, encoding="utf-8")
    return path


def error_of(path) -> str:
    with pytest.raises(CellError) as info:
        load_cell(path)
    return str(info.value)


def test_a_search_too_fast_for_the_goal_is_refused_from_the_read_period(tmp_path):
    """search_speed_mm_s = 50 generated; the TCP came out 0.111 mm off against the 0.1 mm goal. KUKA reads its
    inputs every 12 ms: the tip is seen up to 0.6 mm late, half of it stays in the contact."""
    says = error_of(edited(tmp_path, ("search_speed_mm_s = 2.0", "search_speed_mm_s = 50")))
    assert (
        "laser.search_speed_mm_s: kuka reads its inputs every 12 ms: at 50 mm/s the tip search sees the tip up to"
        in (says)
    )
    assert "0.600 mm late" in says and "beyond the 0.1 mm goal: at most 2.9 mm/s here" in says


def test_the_same_search_speed_meets_the_goal_where_the_inputs_are_read_every_2_ms(tmp_path):
    cell = load_cell(edited(tmp_path, *UR_ONLY, ("search_speed_mm_s = 2.0", "search_speed_mm_s = 40")))
    assert cell.sections["laser"].search_speed_mm_s == 40.0


def test_circles_too_fast_for_the_goal_name_the_circle_speed(tmp_path):
    """15 mm/s on KUKA: each edge up to 0.18 mm late, the centres put the TCP 0.12 mm off before any search."""
    says = error_of(edited(tmp_path, ("circle_speed_mm_s = 10.0", "circle_speed_mm_s = 15.0")))
    assert "laser.circle_speed_mm_s: kuka reads its inputs every 12 ms: at 15 mm/s the circles' centres alone" in says


def test_an_offset_max_below_the_tcps_error_is_refused(tmp_path):
    """offset_max_mm = 1e-9 generated (written as 0.0000): the program then stops on a correct tool."""
    says = error_of(edited(tmp_path, ("offset_max_mm = 3.0 ", "offset_max_mm = 1e-9 ")))
    assert "laser.offset_max_mm: ur reads its inputs every 2 ms: it finds a correct tool's TCP up to 0.020 mm off" in (
        says
    )


def test_a_numbered_kuka_tool_verifies_and_receives_the_tcp_found(tmp_path):
    """`[cell.tool] numbered = { kuka = 3 }` generated, then every KUKA case failed ("FRAME.X has no value"). The
    program calibrates TOOL_DATA[3] and writes the TCP it finds there: verify loads it as $config.dat holds it and
    reads it back."""
    path = edited(tmp_path, ("cog_mm = [0.0, 0.0, 70.0]", "cog_mm = [0.0, 0.0, 70.0]\nnumbered = { kuka = 3 }"))
    cell = load_cell(path)
    programs = sources(cell, "kuka", "laser")
    assert "TOOL_DATA[3]" in programs[0].files[0].text
    rows = verify(cell, programs, cases=1, scenarios=frozenset({"nominal"}))
    assert rows[0].cases >= 5 and rows[0].mismatches == 0, rows[0].first_mismatches[:2]


@pytest.mark.parametrize(
    ("old", "new"),
    [
        ("circle_speed_mm_s = 10.0", "circle_speed_mm_s = 1e-300"),  # generated, the speed written as 0.000
        ("search_speed_mm_s = 2.0", "search_speed_mm_s = 0.5"),
    ],
)
def test_speeds_below_the_programs_least_are_refused(tmp_path, old, new):
    """A laser speed the programs would write as 0 (KRL's $VEL.CP in m/s to 4 decimals), as [cell.motion]'s."""
    key = old.split(" ")[0]
    assert f"laser.{key}: must be in [1, " in error_of(edited(tmp_path, (old, new)))
    laser = load_cell(edited(tmp_path, (old, f"{key} = 1.0"))).sections["laser"]
    assert getattr(laser, key) == 1.0
