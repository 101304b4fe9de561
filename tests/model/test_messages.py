"""Messages about a cell file's shape: a kind's table that is not a table is named as such (not as a missing table
of another kind), and the elements of every array of tables are counted one way (from 0, as the loader counts)."""

from __future__ import annotations

import pytest

from codegen.model.cell import DEMO_CELL, EXAMPLES_DIR, CellError, load_cell

BELT = EXAMPLES_DIR / "conveyor" / "belt_pick.toml"
LASER = EXAMPLES_DIR / "laser" / "laser_tcp.toml"
PALLET = EXAMPLES_DIR / "pallets" / "testmat_pallet.toml"


def _error(path) -> str:
    with pytest.raises(CellError) as caught:
        load_cell(path)
    return str(caught.value)


def _with_first_line(source, line: str, drop_from: str | None = None) -> str:
    text = source.read_text(encoding="utf-8")
    if drop_from is not None:
        text = text[: text.index(drop_from)]
    first, rest = text.split("\n", 1)
    return f"{first}\n{line}\n{rest}"


@pytest.mark.parametrize(
    ("source", "line", "drop_from", "says"),
    [
        (BELT, "conveyor = 5", "\n[conveyor]", "line 2: conveyor: expected a table ([conveyor]), got the number 5"),
        (LASER, "station = 5", None, "line 2: station: expected [[station]] tables, got the number 5"),
        (LASER, "pallet = 'x'", None, "line 2: pallet: expected [[pallet]] tables, got"),
        (BELT, "laser = [1, 2]", None, "line 2: laser: expected a table ([laser]), got"),
    ],
)
def test_a_kinds_table_that_is_not_a_table_is_named(write_cell, source, line, drop_from, says):
    """`conveyor = 5` in a belt cell said "cell.camera: missing" (the station kind, seeing no other kind, asked for
    its camera)."""
    error = _error(write_cell(_with_first_line(source, line, drop_from)))
    assert says in error and "cell.camera" not in error


def test_the_first_station_is_station_0_as_the_first_pallet_is_pallet_0(write_cell):
    """[[station]] was counted from 1 (station[1] the first), [[pallet]] and every other array from 0."""
    demo = DEMO_CELL.read_text(encoding="utf-8")
    bad = demo.replace("approach = [", "approach = [1, ", 1)
    error = _error(write_cell(bad))
    assert "station[0].poses.approach: expected 6 numbers, got 7" in error
    assert f"line {bad[: bad.index('approach = [1, ')].count(chr(10)) + 1}: " in error
    pallet = PALLET.read_text(encoding="utf-8").replace("[[pallet]]", "[[pallet]]\nbogus = 1", 1)
    assert "pallet[0].bogus: unknown key" in _error(write_cell(pallet))


EUR = EXAMPLES_DIR / "pallets" / "eur_pallet.toml"


@pytest.mark.parametrize(
    ("source", "old", "new", "says"),
    [
        (  # the pallet's "full" output is the gripper's: closing the gripper told the PLC to swap the pallet
            PALLET,
            'done = { ur = 2, kuka = 22, abb = "doPalletFull"',
            'done = { ur = 0, kuka = 22, abb = "doPalletFull"',
            "pallet[0].io.done.ur: ur output 0 is cell.io.output.ur too: one signal, one job",
        ),
        (  # a box arriving at Q read as the pallet standing in place
            PALLET,
            'pallet_present = { ur = 3, kuka = 20, abb = "diPalletIn"',
            'pallet_present = { ur = 3, kuka = 19, abb = "diPalletIn"',
            "pallet[0].io.pallet_present.kuka: kuka input 19 is pallet[0].io.part_present.kuka too",
        ),
        (  # one select input started both pallets' programs
            EUR,
            'select = { abb = "diRunEurIn" }',
            'select = { abb = "DIRUNEUR" }',
            "pallet[1].io.select.abb: abb input 'DIRUNEUR' is pallet[0].io.select.abb too",
        ),
    ],
)
def test_one_signal_does_one_job(write_cell, source, old, new, says):
    text = source.read_text(encoding="utf-8")
    assert old in text
    assert says in _error(write_cell(text.replace(old, new, 1)))


BELT_PICK = EXAMPLES_DIR / "conveyor" / "belt_pick.toml"


@pytest.mark.parametrize(
    ("source", "key", "says"),
    [
        (PALLET, "box_mass_kg", "pallet[0].box_mass_kg: 500 kg carried by a 0.8 kg tool is more than the UR5e"),
        (BELT_PICK, "part_mass_kg", "conveyor.pick.part_mass_kg: 500 kg carried by a"),
    ],
)
def test_a_carried_box_or_part_within_the_arms_payload(write_cell, source, key, says):
    """A 500 kg box on a 5 kg arm generated, and its programs set the payload the arm cannot take."""
    text = source.read_text(encoding="utf-8")
    start = text.index(f"{key} = ")
    end = text.index("\n", start)
    value = text[start:end].split("=", 1)[1].split("#", 1)[0].strip()
    assert says in _error(write_cell(text[:start] + text[start:end].replace(value, "500.0", 1) + text[end:]))


def test_a_shift_beyond_the_arms_reach_is_refused_before_its_envelope(write_cell):
    """max_shift_mm = 99999 sampled its envelope for minutes and gigabytes (5000: 37 s, 2 GB) before refusing."""
    text = DEMO_CELL.read_text(encoding="utf-8")
    assert "max_shift_mm = 10.0 " in text
    error = _error(write_cell(text.replace("max_shift_mm = 10.0 ", "max_shift_mm = 99999.0", 1)))
    assert "cell.limits.max_shift_mm: 99999 mm is more than the UR10e's reach of 1300 mm (cell.robot.ur)" in error


def test_a_home_at_a_joint_limit_is_refused(write_cell):
    """A home at axis 1's limit (UR: 360 deg) loaded, though every taught pose must keep the joint margin."""
    text = DEMO_CELL.read_text(encoding="utf-8")
    old = "ur = [180.0, -90.0, 90.0, -90.0, -90.0, 0.0]"
    assert old in text
    error = _error(write_cell(text.replace(old, "ur = [360.0, -90.0, 90.0, -90.0, -90.0, 0.0]", 1)))
    assert "cell.robot.home.ur[0]: axis 1 at 360 deg is within 5 deg (cell.robot.joint_margin_deg)" in error
