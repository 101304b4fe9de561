"""Palletizing (source 004): the [[pallet]] section, the frame, the patterns and their checks, `codegen pallet`."""

import json
import math
import shutil
import subprocess
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from support.closed_forms import evaluate

from codegen.cli import main
from codegen.kinds.pallet import checks
from codegen.kinds.pallet.analysis import frame_matrix
from codegen.kinds.pallet.patterns import Box, column, interlock, pinwheel, split_row
from codegen.kinds.pallet.report import load_pallet_file
from codegen.kinds.pallet.stack import FrameError, pallet2base, placements
from codegen.model.cell import CellError, load_cell

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "codegen" / "examples" / "pallets"
TESTMAT = (EXAMPLES / "testmat_pallet.toml").read_text()


def _load(tmp_path, text: str):
    path = tmp_path / "pallet.toml"
    path.write_text(text)
    return load_pallet_file(path)


def test_the_frame_is_orthonormal_when_the_y_point_is_taught_off_square():
    """PY taught 5 deg off square in the pallet plane: y is still square to x (source 004's eq. 1 would
    take PY - O itself as y)."""
    off = math.radians(5)
    frame = pallet2base((10, 20, 30), (110, 20, 30), (10 + 80 * math.sin(off), 20 + 80 * math.cos(off), 30))
    rot = frame[:3, :3]
    assert np.allclose(rot.T @ rot, np.eye(3), atol=1e-12)
    assert np.allclose(rot, np.eye(3), atol=1e-12) and np.allclose(frame[:3, 3], (10, 20, 30))


@pytest.mark.parametrize(
    ("points", "says"),
    [
        (((0, 0, 0), (5, 0, 0), (0, 80, 0)), "x_point is 5 mm from the origin"),
        (((0, 0, 0), (100, 0, 0), (100, 5, 0)), "within 10 deg of one line"),
    ],
)
def test_a_frame_without_a_plane_is_refused(points, says):
    with pytest.raises(FrameError, match=says):
        pallet2base(*points)


def test_a_frame_taught_from_below_warns(tmp_path):
    text = TESTMAT.replace("xy_point = [650.0, 30.0, 50.0]", "xy_point = [650.0, -130.0, 50.0]")
    assert text != TESTMAT
    assert any("z points down" in w for w in _load(tmp_path, text).warnings)


def test_source_004s_test_pallet_as_its_tables_describe():
    """Table 1 (angles clockwise: 90 -> a = -90 as Table 2 writes it), layers 26 mm each, patterns 1 and
    2 alternating (Table 3), approach (5, 5, 5) mm (Table 4); the entry 50 mm above the target (the carried box's
    bottom more than the 20 mm clearance over the layer's tops), not Table 4's 6.5 mm (it would hang below them)."""
    result = json.loads(CliRunner().invoke(main, ["pallet", "--json"]).stdout)
    boxes = result["pallets"][0]["boxes"]
    assert len(boxes) == 30 and [b["pattern"] for b in boxes[::6]] == ["p1", "p2", "p1", "p2", "p1"]
    table1 = {
        "p1": [(13, 26, -90), (39, 26, -90), (65, 26, -90), (91, 26, -90), (26, 65, 0), (78, 65, 0)],
        "p2": [(26, 13, 0), (78, 13, 0), (13, 52, -90), (39, 52, -90), (65, 52, -90), (91, 52, -90)],
    }
    for b in boxes:
        x, y, a = table1[b["pattern"]][b["box"] - 1]
        z = 26 * b["layer"]
        assert b["target"]["pallet"] == [x, y, z, a, 0, 180]
        assert b["entry"]["pallet"] == [x, y, z + 50, a, 0, 180]
        assert b["approach"]["pallet"] == [x + 5, y + 5, z + 5, a, 0, 180]
        # the frame of the example: origin (650, -50, 50), axes those of the base
        assert b["target"]["base"][:3] == [650 + x, -50 + y, 50 + z]


def test_the_octagon_two_squares_make():
    """Two 2 x 2 squares about one centre, one turned 45 deg: a regular octagon of area 8 (sqrt 2 - 1)."""
    found = checks.overlaps((Box(0, 0, 0), Box(0, 0, 45)), (2.0, 2.0))
    assert len(found) == 1 and found[0][:2] == (0, 1) and found[0][2] == pytest.approx(8 * (math.sqrt(2) - 1))
    assert checks.overlaps((Box(0, 0, 0), Box(2, 0, 0)), (2.0, 2.0)) == []  # touching is not overlapping


@pytest.mark.parametrize(
    ("old", "new", "says"),
    [
        (
            "[39, 26, 90], [65, 26, 90]",
            "[30, 26, 90], [65, 26, 90]",
            r"pallet\[0\]\.patterns\.p1: boxes 1 and 2 overlap",
        ),
        ("p2 = [[26, 13, 0]", "p2 = [[20, 13, 0]", r"pallet\[0\]\.patterns\.p2: box 1 reaches 6\.0 mm beyond"),
        ('cycle = ["p1", "p2"]', 'cycle = ["p1", "p3"]', r"pallet\[0\]\.cycle\[1\]: no pattern 'p3'"),
        ("layers = 5", "layers = 0", r"pallet\[0\]\.layers: expected a whole number"),
        ("entry_dz = 50.0", "entry_dz = -1", r"pallet\[0\]\.entry_dz: must be in \(0"),
        ("entry_dz = 50.0", "entry_dz = 25.9", r"pallet\[0\]\.entry_dz: 25\.9 mm .* box's height \(26 mm, box\)"),
        ("entry_dz = 50.0", "transit_clearance_mm = -1\nentry_dz = 50.0", r"pallet\[0\]\.transit_clearance_mm"),
        ("pick_lift = 30.0", "pick_lift = 0.0", r"pallet\[0\]\.pick_lift: must be in \(0, 2000\] mm"),
        ("pick_lift = 30.0", 'pick_lift = "up"', r"pallet\[0\]\.pick_lift: expected a number"),
        ("box = [52.0, 26.0, 26.0]", "box = [52.0, 26.0]", r"pallet\[0\]\.box"),
    ],
)
def test_a_pallet_that_cannot_be_stacked_is_refused_with_its_key(tmp_path, old, new, says):
    assert old in TESTMAT
    with pytest.raises(CellError, match=says):
        _load(tmp_path, TESTMAT.replace(old, new, 1))


def test_an_allowed_overhang_passes_and_the_cli_refuses_with_exit_2(tmp_path):
    text = TESTMAT.replace("p2 = [[26, 13, 0]", "p2 = [[20, 13, 0]")
    _load(tmp_path, text.replace('angle_sense = "cw"', 'angle_sense = "cw"\noverhang_mm = 6'))
    result = CliRunner().invoke(main, ["pallet", str(tmp_path / "pallet.toml")])
    assert result.exit_code == 0
    (tmp_path / "bad.toml").write_text(text)
    result = CliRunner().invoke(main, ["pallet", str(tmp_path / "bad.toml")])
    assert result.exit_code == 2 and "box 1 reaches 6.0 mm beyond" in result.output and "Traceback" not in result.output


@pytest.mark.parametrize(
    ("family", "count"),
    [(column, 8), (interlock, 6), (pinwheel, 4), (split_row, 5)],  # counted by hand on 1200 x 800, 400 x 300
)
def test_every_family_fits_a_eur_pallet_without_overlap(family, count):
    boxes = tuple(family(1200.0, 800.0, 400.0, 300.0))
    assert len(boxes) == count
    assert (
        checks.overlaps(boxes, (400.0, 300.0)) == [] and checks.overhangs(boxes, (400.0, 300.0), (1200.0, 800.0)) == []
    )


def test_a_layer_shifted_half_a_box_rests_half_on_the_one_below():
    lower = (Box(200, 150, 0),)
    assert checks.support((Box(400, 150, 0),), lower, (400.0, 300.0)) == [pytest.approx(0.5)]
    assert checks.support((Box(200, 150, 90),), lower, (400.0, 300.0)) == [pytest.approx(300 * 300 / (400 * 300))]


def test_the_eur_example_slip_sheets_mirror_and_labels(tmp_path):
    data = load_pallet_file(EXAMPLES / "eur_pallet.toml")
    result = json.loads(CliRunner().invoke(main, ["pallet", str(EXAMPLES / "eur_pallet.toml"), "--json"]).stdout)
    tops = [layer["top_mm"] for layer in result["pallets"][0]["layers"]]
    assert tops == [250, 500, 753, 1003, 1256]  # a 3 mm sheet on top of layers 2 and 4
    boxes = result["pallets"][0]["boxes"]
    first, mirrored = boxes[0]["target"]["pallet"], boxes[6]["target"]["pallet"]
    assert mirrored[0] == 1200 - first[0] and mirrored[1] == first[1]
    assert any("50%" in w and "support_min 60%" in w for w in data.warnings)
    cycle = result["pallets"][0]["cycle"]
    # the path at its speeds, less the blended corners' cut (each half at 200 mm/s at most, at 1000 mm/s at least)
    straight = cycle["travel_mm"] / 1000 + cycle["work_mm"] / 200
    cut = cycle["corner_saving_mm"]
    assert straight - cut / 200 - 0.1 <= cycle["seconds"] <= straight - cut / 1000 + 0.1


def test_the_cycle_estimate_counts_each_segment_at_its_own_speed():
    """Source 004's pallet, 30 boxes: at the work speed only entry -> approach, |(5, 5, 5 - 50)| (the entry 50 mm
    above the target, the approach (5, 5, 5)), approach -> target and target -> retreat, each |(5, 5, 5)| = 8.66 mm
    long, and down to Q and back up, the cell's pick_lift of 30 mm each; retreat -> entry at travel."""
    result = json.loads(CliRunner().invoke(main, ["pallet", "--json"]).stdout)
    cycle = result["pallets"][0]["cycle"]
    assert cycle["work_mm"] == pytest.approx(
        30 * (math.sqrt(5**2 + 5**2 + 45**2) + 2 * math.sqrt(75) + 2 * 30.0), abs=0.1
    )


def test_the_pictures_show_each_box_numbered_with_its_label_and_approach(tmp_path):
    result = CliRunner().invoke(main, ["pallet", "--svg", str(tmp_path)])
    assert result.exit_code == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"testmat_layer{n:02d}.svg" for n in range(1, 6)]
    ns = {"s": "http://www.w3.org/2000/svg"}
    root = ET.parse(tmp_path / "testmat_layer01.svg").getroot()
    assert "layer 1 of 5, pattern p1, top at z 26 mm" in root.find("s:title", ns).text
    polygons = root.findall("s:polygon", ns)
    numbers = [t.text for t in root.findall("s:text", ns) if t.get("class") == "number"]
    assert len(polygons) == 6 and numbers == ["1", "2", "3", "4", "5", "6"]
    assert (
        len(root.findall("s:line[@class='label']", ns)) == 6 and len(root.findall("s:line[@class='approach']", ns)) == 6
    )
    # box 1 of pattern 1 stands turned, 26 mm along the pallet's x and 52 mm along its y: its outline says so
    points = np.array([[float(v) for v in p.split(",")] for p in polygons[0].get("points").split()])
    width_px, height_px = np.ptp(points[:, 0]), np.ptp(points[:, 1])
    assert height_px == pytest.approx(2 * width_px, rel=1e-3)


def test_the_automatic_approach_comes_from_the_open_side():
    """EUR example, layer 1: box 1 (200, 250) has nothing placed before it: away from the pallet's
    centre (600, 400); box 2 (200, 550) comes from +y, away from box 1; the length stays 30 sqrt 2."""
    result = json.loads(CliRunner().invoke(main, ["pallet", str(EXAMPLES / "eur_pallet.toml"), "--json"]).stdout)
    box1, box2 = result["pallets"][0]["boxes"][:2]
    length = 30 * math.sqrt(2)
    away = np.array([200 - 600, 250 - 400]) / math.hypot(400, 150) * length
    assert box1["approach"]["pallet"][:2] == pytest.approx([200 + away[0], 250 + away[1]], abs=1e-6)
    assert box2["approach"]["pallet"][:3] == pytest.approx([200, 550 + length, 250 + 60], abs=1e-6)
    assert box2["retreat"]["pallet"][:2] == pytest.approx([200, 550 + length], abs=1e-6)


@pytest.mark.parametrize(
    ("old", "new", "says"),
    [
        # Q 1.2 m away: beyond a 0.9 m arm
        (
            "pick = [600.0, 300.0, 50.0,",
            "pick = [1200.0, 300.0, 50.0,",
            r"layer 1 box 1 above Q \(ur, UR5e\): out of reach: the flange would be at \(1200, 300, \d+\) mm, "
            r"[\d,]+ mm from the base, beyond the UR5e's reach of 850 mm",
        ),
        # the pallet 250 mm lower and nearer: the KR 6's wrist passes within 1 deg of its singularity
        (
            "origin = [650.0, -50.0, 50.0], x_point = [750.0, -50.0, 50.0], xy_point = [650.0, 30.0, 50.0]",
            "origin = [500.0, -100.0, -200.0], x_point = [600.0, -100.0, -200.0], xy_point = [500.0, -20.0, -200.0]",
            r"\(kuka, KR 6 R900 sixx\): .* the wrist 0\.\d deg from its singularity; the cell asks 5 and 5 deg",
        ),
    ],
)
def test_a_stack_the_arm_cannot_work_is_refused_at_generate(tmp_path, old, new, says):
    from codegen.generate import GenerateError, check_envelope

    assert old in TESTMAT
    path = tmp_path / "pallet.toml"
    floor = "[cell.world]\nfloor_z_mm = -400.0\n\n[cell.io]"  # under the lowered pallet (its top at -200 mm)
    path.write_text(TESTMAT.replace(old, new, 1).replace("[cell.io]", floor, 1))
    with pytest.raises(GenerateError, match=says):
        check_envelope(load_cell(path), None)


def test_the_bundled_stack_is_reachable_on_every_arm():
    from codegen.kinds.pallet.plan import check

    reports = check(load_cell(EXAMPLES / "testmat_pallet.toml"))
    # 30 boxes of 10 moves (up from Q to the transit height, above the entry there), 29 of them 2 more (the empty
    # gripper from the entry before over Q at that height, then down above Q, where the first's joint move goes
    # above Q), the 2 moves off the pallet at the end (over Q, above Q), the way home's pose above the pallet
    assert [r.target for r in reports] == ["ur", "kuka", "abb"] and all(r.moves == 300 + 29 + 2 + 1 for r in reports)
    assert all(r.joint_margin_deg >= 5 and r.wrist_margin_deg >= 5 for r in reports)


CHROMIUM = shutil.which("chromium-headless-shell") or shutil.which("chromium")


def _rendered(svg: str, renderer: str):
    """The picture as people see it, as an RGB image: drawn by headless Chromium (Debian's
    chromium-headless-shell, which .ci/run installs) or by resvg (a second, independent renderer)."""
    import io

    from PIL import Image

    if renderer == "resvg":
        import resvg_py

        return Image.open(io.BytesIO(resvg_py.svg_to_bytes(svg_string=svg, background="#ffffff"))).convert("RGB")
    if CHROMIUM is None:
        pytest.skip("headless Chromium is not installed (Debian: apt-get install chromium-headless-shell)")
    root = ET.fromstring(svg)
    size = f"{root.get('width')},{root.get('height')}"
    with tempfile.TemporaryDirectory() as folder:
        page, shot = Path(folder) / "layer.svg", Path(folder) / "layer.png"
        page.write_text(svg, encoding="utf-8")
        flags = ["--no-sandbox", "--hide-scrollbars", "--force-device-scale-factor=1", f"--window-size={size}"]
        subprocess.run(
            [CHROMIUM, "--headless", *flags, f"--screenshot={shot}", page.as_uri()],
            check=True,
            capture_output=True,
            timeout=60,
        )
        return Image.open(shot).convert("RGB")


def _to_px(root, x_mm: float, y_mm: float) -> tuple[int, int]:
    """Pallet mm to picture pixels, from the pallet's outline in the SVG (its x to the right, y up)."""
    ns = {"s": "http://www.w3.org/2000/svg"}
    rect = root.find("s:rect[@class='pallet']", ns)
    left, top = float(rect.get("x")), float(rect.get("y"))
    width, height = float(rect.get("width")), float(rect.get("height"))
    return round(left + x_mm / 104.0 * width), round(top + height - y_mm / 78.0 * height)


@pytest.mark.parametrize("renderer", ["chromium", "resvg"])
def test_the_rendered_layer_shows_boxes_labels_approach_and_overhang_in_red(tmp_path, renderer):
    """Source 004's layer 1: boxes 1-4 turned (26 x 52 mm) along the bottom, 5-6 along the top; box 1's
    label (its long side at -y when unturned) faces +x; an arrow on every box; no red. A box moved 6 mm
    over the edge (allowed by overhang_mm) is drawn red."""
    from codegen.kinds.pallet.pictures import layer_svg
    from codegen.kinds.pallet.shape import PalletShape

    data = _load(tmp_path, TESTMAT)
    svg = layer_svg(PalletShape.of(data.pallets[0]), 1)
    image, root = _rendered(svg, renderer), ET.fromstring(svg)
    fill, label, arrow = (255, 248, 231), (42, 157, 143), (31, 95, 191)
    assert image.getpixel(_to_px(root, 6, 8)) == fill  # box 1, away from its arrow and number
    assert image.getpixel(_to_px(root, 26, 70)) == fill  # box 5
    assert image.getpixel(_to_px(root, 100, 60)) == fill  # box 6
    assert image.getpixel(_to_px(root, 5, 45)) == fill  # box 1 again: turned, it reaches y 52
    assert image.getpixel(_to_px(root, 26, 30)) == label  # box 1's label side at x 26 (it faces +x)
    colours = image.getcolors(maxcolors=100_000)
    assert sum(n for n, c in colours if c == arrow) > 6 * 10  # six arrows
    assert not any(r > 180 and g < 100 and b < 100 for _n, (r, g, b) in colours)
    over = TESTMAT.replace("p2 = [[26, 13, 0]", "p2 = [[20, 13, 0]").replace(
        'angle_sense = "cw"', 'angle_sense = "cw"\noverhang_mm = 6'
    )
    layer2 = _rendered(layer_svg(PalletShape.of(_load(tmp_path, over).pallets[0]), 2), renderer)
    reddish = sum(n for n, (r, g, b) in layer2.getcolors(maxcolors=100_000) if r > 180 and g < 100 and b < 100)
    assert reddish > 100  # box 1's outline


def test_split_row_on_a_pallet_its_shifted_rows_fill_further():
    """1000 mm of 400 mm boxes: full rows of 2 (800 mm), shifted rows from 200 to 1000 mm: the layout is
    centred on the wider extent, so it stays on the pallet."""
    boxes = tuple(split_row(1000.0, 800.0, 400.0, 300.0))
    assert len(boxes) == 4 and checks.overhangs(boxes, (400.0, 300.0), (1000.0, 800.0)) == []


def test_a_cycle_entry_that_is_no_name_is_refused(tmp_path):
    with pytest.raises(CellError, match=r"pallet\[0\]\.cycle\[0\]: expected a string, got a list of 1"):
        _load(tmp_path, TESTMAT.replace('cycle = ["p1", "p2"]', 'cycle = [["p1"], "p2"]'))


def test_a_pallet_named_like_the_cells_program_or_beyond_the_registers_is_refused(tmp_path):
    """A pallet program named like the cell's vision program is refused (EmitError naming both); the UR counters
    are PLC data on the fieldbus registers 0..23, two per pallet: a 13th pallet is refused by its key."""
    from codegen.emit import EmitError
    from codegen.render import render

    demo = (REPO / "codegen" / "examples" / "agv_machine_tending.toml").read_text()
    pallet = TESTMAT[TESTMAT.index("[[pallet]]") :].replace('name = "testmat"', 'name = "agv_machine_tending"', 1)
    cell = tmp_path / "cell.toml"
    cell.write_text(demo.replace('name = "agv_machine_tending"', 'name = "pal_agv_machine_tending"', 1) + "\n" + pallet)
    with pytest.raises(EmitError, match="both map to the identifier"):
        render(load_cell(cell), ["ur"])
    many = []
    for i in range(11):  # 10 pallets' counters fit registers 0..19
        one = pallet.replace('name = "agv_machine_tending"', f'name = "p{i}"', 1)
        one = one.replace("base_data = 1 ", f"base_data = {i + 1} ", 1)  # each pallet its own KUKA base
        many.append(one.replace("timeout_s = 10.0", f'timeout_s = 10.0\nselect = {{ abb = "diP{i}" }}', 1))
    cell.write_text(demo + "\n" + "".join(many))
    with pytest.raises(
        CellError,
        match=r"pallet\[10\]\.io\.registers\.ur \(not in the file: its default\): pallet 11's counters would "
        r"need registers 20 and 21",
    ):
        load_cell(cell)


def test_an_abb_task_with_a_station_program_and_pallets_is_refused(tmp_path):
    """The ABB pallet programs run in one task with their own PROC main; the cell's station program has one too: two
    mains in one task are refused at generate (put the pallets in a cell file of their own)."""
    from codegen.emit import EmitError
    from codegen.render import render

    demo = (REPO / "codegen" / "examples" / "agv_machine_tending.toml").read_text()
    cell = tmp_path / "cell.toml"
    cell.write_text(demo + "\n" + TESTMAT[TESTMAT.index("[[pallet]]") :])
    loaded = load_cell(cell)
    render(loaded, ["ur", "kuka"])
    with pytest.raises(EmitError, match="PROC main"):
        render(loaded, ["abb"])


def test_the_printed_box_position_is_the_pose_product():
    """The level-pallet position the dtrans program computes is printed from the derivation; evaluated in
    float64 (the cached block) for every box of the EUR example's turned pallet it equals pallet2base @
    target of the numpy stack (codegen/kinds/pallet/stack.py)."""
    cell = load_cell(EXAMPLES / "eur_pallet.toml")
    pallet = cell.sections["pallet"][1]  # turned 90 deg about the base's z
    frame = frame_matrix(pallet)
    turn = math.atan2(frame[1, 0], frame[0, 0])
    assert abs(turn) > 1.0
    for p in placements(pallet):
        got = evaluate(
            "box",
            {
                "PAL_OX": frame[0, 3],
                "PAL_OY": frame[1, 3],
                "PAL_COS": math.cos(turn),
                "PAL_SIN": math.sin(turn),
                "x": p.box.x,
                "y": p.box.y,
            },
        )
        want = (frame @ p.target)[:2, 3]
        assert [got["box_px"], got["box_py"]] == pytest.approx(want, abs=1e-9)


def test_svg_files_leave_a_symlink_to_a_users_file_alone(tmp_path):
    """A symlink named like a layer's picture, to a file codegen did not write: link and file are left as they
    were, and no picture is written (codegen.writefile's rule for every file the user names)."""
    mine = tmp_path / "mine.txt"
    mine.write_text("mine")
    folder = tmp_path / "svg"
    folder.mkdir()
    (folder / "testmat_layer01.svg").symlink_to(mine)
    result = CliRunner().invoke(main, ["pallet", "--svg", str(folder)])
    assert result.exit_code == 2 and "was not written by codegen; left alone" in result.output, result.output
    assert mine.read_text() == "mine" and (folder / "testmat_layer01.svg").is_symlink()
    assert sorted(p.name for p in folder.iterdir()) == ["testmat_layer01.svg"]


@pytest.mark.parametrize("blocked", ["folder is a file", "picture is a folder"])
def test_svg_into_a_place_that_cannot_take_it_gets_one_message(tmp_path, blocked):
    folder = tmp_path / "svg"
    if blocked == "folder is a file":
        folder.write_text("mine")
        where = folder / "sub"
    else:
        (folder / "testmat_layer02.svg").mkdir(parents=True)
        where = folder
    result = CliRunner().invoke(main, ["pallet", "--svg", str(where)])
    assert result.exit_code == 2 and "Traceback" not in result.output, result.output
    errors = [line for line in result.output.splitlines() if line.startswith("Error")]
    assert len(errors) == 1 and "cannot write the pictures" in errors[0], result.output
    assert not list(tmp_path.rglob("*.tmp"))
