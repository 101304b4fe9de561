"""The [[pallet]] numbers a fault probe broke: boxes beyond what verify and generate can work, angles, whole numbers."""

from __future__ import annotations

import random
import subprocess
import sys
import time

import numpy as np
import pytest
from support.cells import EXAMPLES
from support.programs import sources, verify

from codegen.kinds.pallet import checks
from codegen.kinds.pallet.patterns import Box
from codegen.model.cell import CellError, load_cell


def edited(tmp_path, example: str, *changes: tuple[str, str]):
    text = EXAMPLES[example].read_text(encoding="utf-8")
    for old, new in changes:
        assert old in text, f"{example}: {old!r} not found"
        text = text.replace(old, new, 1)
    path = tmp_path / f"{example}.toml"
    path.write_text(text, encoding="utf-8")
    return path


def error_of(path) -> str:
    with pytest.raises(CellError) as info:
        load_cell(path)
    return str(info.value)


def test_a_three_millimetre_box_on_a_eur_pallet_is_refused_at_once(tmp_path):
    """960,000 boxes a layer (a 1 mm box): generate gave no answer in 120 s. Refused before any layer is made (3 mm:
    a box of 1 mm is asked about as metres first)."""
    path = edited(tmp_path, "eur_pallet", ("box = [400.0, 300.0, 250.0]", "box = [3.0, 3.0, 3.0]"))
    start = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-m", "codegen", "generate", str(path), "--out", str(tmp_path / "out")],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "pallet[0].patterns.interlock: 106400 boxes of 3 x 3 mm make this family's layer; at most 2000" in (
        proc.stderr
    )
    assert time.perf_counter() - start < 30


def test_a_column_of_250000_boxes_is_refused_without_the_quadratic_array(tmp_path):
    """size 5000 x 5000, box 10 x 10, a column: the overlap check asked for 116 GiB."""
    path = edited(
        tmp_path,
        "eur_pallet",
        ("size = [1200.0, 800.0]", "size = [5000, 5000]"),
        ("box = [400.0, 300.0, 250.0]", "box = [10, 10, 10]"),
        ('interlock = { family = "interlock", label_out = true }', 'interlock = { family = "column" }'),
    )
    assert "pallet[0].patterns.interlock: 250000 boxes of 10 x 10 mm" in error_of(path)


def test_every_family_counts_before_it_builds():
    """A box of a micrometre: each family refuses with its count instead of making it (or looping over it)."""
    from codegen.kinds.pallet.patterns import FAMILIES, TooManyBoxes

    for name, family in FAMILIES.items():
        with pytest.raises(TooManyBoxes) as info:
            family(5000.0, 5000.0, 1e-3, 1e-3)
        assert info.value.count > 2000, name
        with pytest.raises(TooManyBoxes):
            family(5000.0, 5000.0, 1e-300, 1e-300)  # 5000 // 1e-300 is inf as a float


def test_a_stack_beyond_the_bound_names_its_layers(tmp_path):
    # 40 x 40 mm boxes: a column of 30 x 20 = 600 a layer, 5 layers: 3,000 boxes
    column = ('interlock = { family = "interlock", label_out = true }', 'interlock = { family = "column" }')
    mirrored = ('interlock_mirrored = { family = "interlock", label_out = true, mirror = true }', "")
    cycle = ('cycle = ["interlock", "interlock_mirrored"]', 'cycle = ["interlock"]')
    box = ("box = [400.0, 300.0, 250.0]", "box = [40.0, 40.0, 40.0]")
    path = edited(tmp_path, "eur_pallet", box, column, mirrored, cycle)
    says = error_of(path)
    assert "pallet[0].layers: 5 layers of the cycle's patterns make 3000 boxes; at most 2000 a stack" in says
    path = edited(tmp_path, "eur_pallet", box, column, mirrored, cycle, ("layers = 5 ", "layers = 3 "))
    assert len(load_cell(path).sections["pallet"][0].cycle) == 1  # 1,800 boxes: within the bound


def test_an_explicit_pattern_longer_than_the_bound_is_refused_before_its_boxes_are_read(tmp_path):
    boxes = ", ".join("[13, 26, 90]" for _ in range(2001))
    path = edited(tmp_path, "testmat_pallet", ("p1 = [[13, 26, 90], ", f"p1 = [{boxes}, "))
    assert "pallet[0].patterns.p1: 2006 boxes; at most 2000 a pattern" in error_of(path)


@pytest.mark.parametrize(
    ("old", "new", "says"),
    [
        # turned every box 28 deg in float32 on every target (the same as 180 in exact arithmetic)
        (
            "tool_orientation = [0.0, 0.0, 180.0]",
            "tool_orientation = [0, 0, 999999900.0]",
            r"pallet[0].tool_orientation: angles must be within +-360 deg",
        ),
        (
            "[13, 26, 90], [39, 26, 90]",
            "[13, 26, 1e9], [39, 26, 90]",
            "pallet[0].patterns.p1[0][2]: must be in [-5000, 5000] (a box: x, y (mm), angle (deg)), got 1e+09",
        ),
        ("[13, 26, 90], [39, 26, 90]", "[13, 26, 400], [39, 26, 90]", "pallet[0].patterns.p1[0]: the angle must be"),
        ("x_point = [750.0, -50.0, 50.0]", "x_point = [1e9, -50.0, 50.0]", "pallet[0].frame.x_point: a taught point"),
        ("origin = [650.0, -50.0, 50.0]", "origin = [650.0, -1e300, 50.0]", "pallet[0].frame.origin: a taught point"),
        ("layers = 5", "layers = 5.0", "pallet[0].layers: expected a whole number (no decimal point) in 1..200"),
        ('cycle = ["p1", "p2"]', "cycle = [" + '"p1", ' * 201 + '"p2"]', "pallet[0].cycle: 202 patterns; at most 200"),
    ],
)
def test_pallet_numbers_the_programs_cannot_meet_are_refused(tmp_path, old, new, says):
    assert says in error_of(edited(tmp_path, "testmat_pallet", (old, new)))


def test_slip_sheets_every_n_th_layer_is_a_whole_number(tmp_path):
    path = edited(tmp_path, "eur_pallet", ("every = 2,", "every = 2.0,"))
    assert "pallet[0].slip_sheet.every: expected a whole number (no decimal point)" in error_of(path)


def test_the_overlap_pass_in_chunks_finds_the_pairs_of_the_whole_comparison(monkeypatch):
    """The bounding-box pass compared in chunks of rows gives the pairs (and their order) of one comparison."""
    rng = random.Random(3)
    boxes = [Box(rng.uniform(0, 300), rng.uniform(0, 200), rng.choice([0.0, 90.0, 30.0])) for _ in range(60)]
    shapes = [checks.corners(b, 40.0, 25.0) for b in boxes]
    lo, hi = np.array([s.min(0) for s in shapes]), np.array([s.max(0) for s in shapes])
    whole = [
        (i, j)
        for i in range(len(shapes))
        for j in range(len(shapes))
        if np.all(lo[i] < hi[j]) and np.all(lo[j] < hi[i])
    ]
    monkeypatch.setattr(checks, "CHUNK", 7)
    assert checks._candidates(shapes, shapes) == whole
    assert len(whole) > len(shapes)  # some pairs besides each box with itself


def test_a_numbered_kuka_tool_verifies_in_a_pallet_cell(tmp_path):
    """`[cell.tool] numbered = { kuka = 3 }` generated, then every KUKA case failed ("FRAME.X has no value"): the
    program selects TOOL_DATA[3], which verify did not load as the controller's $config.dat holds it."""
    path = edited(
        tmp_path, "testmat_pallet", ("numbered = { kuka = 1 }", "numbered = { kuka = 3 }")  # the bundled cell's 1
    )
    cell = load_cell(path)
    programs = sources(cell, "kuka", "pallet")
    assert "$TOOL = TOOL_DATA[3]" in programs[0].files[0].text
    rows = verify(cell, programs, cases=1)
    assert rows[0].cases > 5 and rows[0].mismatches == 0, rows[0].first_mismatches[:2]
