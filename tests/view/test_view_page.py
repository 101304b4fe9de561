"""`codegen view`'s page of every bundled cell, loaded in headless Chromium: offline, small, the interpreter's joints,
the catalogue's kinematics, and the arm's and the boxes' colours where they must be on the screen."""

from __future__ import annotations

import colorsys
import itertools
import json
import re

import numpy as np
import pytest

from codegen.kinds.pallet.stack import placements
from codegen.kinds.station.section import stations_of
from codegen.model.cell import EXAMPLES_DIR, example_cells, load_cell
from codegen.robot.expect import arm_of
from codegen.verify.programs import fresh_sources
from codegen.verify.report import case_text
from codegen.view.page import cell_page

CELLS = [p.relative_to(EXAMPLES_DIR).as_posix() for p in example_cells()]
MAX_BYTES = 3_000_000  # a page to attach to a pull request: a few MB at most
LOADING = re.compile(r"<(script|link|img|iframe|object|embed)\b[^>]*\b(src|href|data)\s*=", re.IGNORECASE)


def _data(html: str) -> dict:
    start = html.index('<script id="view-data" type="application/json">') + len('<script id="view-data" ')
    start = html.index(">", start) + 1
    return json.loads(html[start : html.index("</script>", start)])


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    """Each bundled cell's page, every target, written once for the module."""
    folder = tmp_path_factory.mktemp("pages")
    out = {}
    for name in CELLS:
        cell = load_cell(EXAMPLES_DIR / name)
        html = cell_page(cell, list(cell.targets))
        path = folder / f"{cell.name}.html"
        path.write_text(html, encoding="utf-8")
        out[cell.name] = (cell, path, html)
    return out


def test_six_bundled_cells():
    assert len(CELLS) == 6


def test_each_page_is_one_file_that_loads_nothing_and_is_small(pages):
    for name, (_cell, path, html) in pages.items():
        assert path.stat().st_size < MAX_BYTES, name
        assert not LOADING.search(html), f"{name}: the page loads a file or address"
        assert "@import" not in html and "url(" not in html.split("<script>", 1)[0], name
        assert 'content="codegen view' in html[:2000]


def test_every_program_of_every_target_shows_a_nominal_run(pages):
    """The station program: one pass of each station; a pallet program: the whole pallet from layer 1 box 1 (or
    all of it back off); the belt: a part picked; the laser: a TCP calibration; every run to its end."""
    for name, (cell, _path, html) in pages.items():
        data = _data(html)
        assert [v["target"] for v in data["views"]] == list(cell.targets)
        for view in data["views"]:
            assert (view["arm"] is None) == (arm_of(cell, view["target"]) is None)
            programs = {(p["kind"], p["program"]) for p in view["programs"]}
            assert programs == {(s.kind, s.ident) for s in fresh_sources(cell, [view["target"]])}
            for program in view["programs"]:
                where = f"{name} {view['target']} {program['program']}"
                assert program["problem"] is None and program["runs"], where
                assert all(run["halt"] is None and run["moves"] for run in program["runs"]), where
                whats = [run["what"] for run in program["runs"]]
                if stations_of(cell):
                    shown = [int(re.search(r"station (\d+)", w).group(1)) for w in whats]
                    assert shown == [s.id for s in stations_of(cell)], where
                else:
                    assert len(whats) == 1, where
                if program["kind"] == "pallet":
                    assert whats[0].split()[0] in ("full_stack", "full_unstack"), where


def _case_named(cell, source, what: str):
    kind = cell.kinds[source.kind].verify
    for case in kind.cases(cell, source, 1, 0):
        if case_text(kind, cell, case) == what:
            return case
    raise AssertionError(f"no case {what!r}")


@pytest.mark.parametrize("name", ["agv_machine_tending", "belt_pick", "eur_pallet", "laser_tcp", "thermometer_bench"])
def test_the_page_holds_the_interpreters_joints_and_poses(pages, browser, name):
    """Read in the browser, every move of every run: the joints exactly as the interpreter solved them (the case run
    again here, as verify runs it), the pose to the page's rounding, the program line."""
    cell, path, _html = pages[name]
    browser.open(path)
    data = browser.evaluate("codegenView.data")
    assert browser.errors() == []
    for view in data["views"]:
        target = view["target"]
        sources = {(s.kind, s.ident): s for s in fresh_sources(cell, [target])}
        for program in view["programs"]:
            source = sources[(program["kind"], program["program"])]
            loaded, kind = source.load(), cell.kinds[source.kind].verify
            for run in program["runs"]:
                setup = kind.setup(cell, source, _case_named(cell, source, run["what"]))
                trace = loaded.run(setup.inputs, **setup.run_options(arm_of(cell, target), 2_000_000))
                assert len(trace.moves) == len(run["moves"])
                for move, shown in zip(trace.moves, run["moves"], strict=True):
                    assert shown["line"] == move.line and shown["kind"] == move.kind
                    if move.joints is None:
                        assert shown["joints"] is None
                    else:
                        assert shown["joints"] == [float(v) for v in move.joints]
                    if move.tcp2base is not None:
                        assert np.allclose(np.reshape(shown["pose"], (4, 4)), move.tcp2base, rtol=0, atol=1e-6)


def test_the_arm_is_drawn_from_the_catalogue_kinematics(pages, browser):
    """The page's forward kinematics of every move's joints: the flange where codegen/robot's fk puts it, the wrist
    centre where wrist_center does, and the tool's TCP on the trace's pose (UR and ortho-parallel arms)."""
    checked = set()
    for name in ("agv_machine_tending", "eur_pallet"):
        cell, path, _html = pages[name]
        browser.open(path)
        data = browser.evaluate("codegenView.data")
        for v, view in enumerate(data["views"]):
            if view["arm"] is None:
                continue
            arm = arm_of(cell, view["target"])
            tool = np.reshape(view["arm"]["tcp2flange"], (4, 4))
            moves = [m for p in view["programs"] for r in p["runs"] for m in r["moves"] if m["joints"] is not None]
            drawn = browser.evaluate(f"{json.dumps([m['joints'] for m in moves])}.map(q => codegenView.fk({v}, q))")
            for move, chain in zip(moves, drawn, strict=True):
                q = np.array(move["joints"])
                flange = np.reshape(chain["flange"], (4, 4))
                assert np.allclose(flange, arm.kin.fk(q), rtol=0, atol=1e-6)
                assert np.allclose(chain["wrist"], arm.kin.wrist_center(q), rtol=0, atol=1e-6)
                assert np.allclose(flange @ tool, np.reshape(move["pose"], (4, 4)), rtol=0, atol=1e-4)
            checked.add(arm.family)
    assert checked == {"ur", "opw"}


def _hsv(pixel) -> tuple[float, float, float]:
    return colorsys.rgb_to_hsv(*(c / 255 for c in pixel))


def is_arm(pixel) -> bool:
    """The arm's orange (#ff6a00) as shaded: hue 15-35 deg, fully saturated."""
    h, s, v = _hsv(pixel)
    return 0.04 <= h <= 0.10 and s > 0.85 and v > 0.3


def is_box(pixel) -> bool:
    """A box's carton (#c8a165) as shaded: hue 25-50 deg, half saturated."""
    h, s, v = _hsv(pixel)
    return 0.07 <= h <= 0.14 and 0.3 < s < 0.7 and v > 0.4


def is_joint(pixel) -> bool:
    """The arm's dark grey joints and base (#333333 as shaded): unsaturated and dark."""
    _h, s, v = _hsv(pixel)
    return s < 0.2 and v < 0.3


def _near(image, xy, test, radius: int = 2) -> bool:
    x, y = round(xy[0]), round(xy[1])
    return any(
        test(image.getpixel((x + dx, y + dy)))
        for dx in range(-radius, radius + 1)
        for dy in range(-radius, radius + 1)
        if 0 <= x + dx < image.width and 0 <= y + dy < image.height
    )


def _show(browser, fragment: str):
    """Move the page (its fragment), then its state, the arm's link midpoints on the screen and a screenshot."""
    state = browser.evaluate(
        f"new Promise(done => {{ location.hash = {json.dumps(fragment)}; "
        "setTimeout(() => done(codegenView.state()), 100); })"
    )
    links = []
    if state["joints"] is not None:
        points = browser.evaluate(f"codegenView.fk({state['view']}, codegenView.state().joints).points")
        mids = [[(a + b) / 2 for a, b in zip(p, q, strict=True)] for p, q in itertools.pairwise(points)]
        links = browser.evaluate(f"{json.dumps(mids)}.map(p => codegenView.project(p))")
    return state, links, browser.screenshot()


def test_each_pallet_run_places_or_takes_every_box_of_its_pallet(pages):
    """The boxes a pallet program's run reaches, in the page: every box of its pallet (the stacking program places
    them, the unstacking one takes them), each at the move that ends on the box's top centre, in the pallet's
    order (placements: layer by layer from the bottom)."""
    cell, _path, html = pages["eur_pallet"]
    data = _data(html)
    pallets = cell.sections["pallet"]
    for view in data["views"]:
        for index, program in enumerate(view["programs"]):
            pallet = pallets[index]
            (run,) = program["runs"]
            boxes = [e for e in run["boxes"] if data["objects"][e[0]]["role"] == "box"]
            assert [data["objects"][i]["label"] for i, _k, _p in sorted(boxes, key=lambda e: e[1])] == [
                f"{pallet.name}: layer {p.layer} box {p.number}"
                for p in (placements(pallet) if pallet.mode == "stack" else reversed(placements(pallet)))
            ]
            assert {placing for _i, _k, placing in boxes} == {1 if pallet.mode == "stack" else 0}
            for i, k, _p in boxes:
                box = data["objects"][i]
                pose = np.reshape(box["pose"], (4, 4))
                top = pose[:3, 3] + pose[:3, 2] * box["size"][2] / 2
                assert np.linalg.norm(np.array(run["moves"][k]["pose"][3:12:4]) - top) < 1e-3


def test_the_arm_and_the_boxes_are_on_the_screen_where_they_must_be(pages, browser):
    """The pallet cell on KUKA: at the start of the stacking cycle the top layer's boxes are not there yet (drawn as
    ghosts); at its end the arm's orange is at the middle of its links, the boxes' carton at the middle of the top
    of every box of the top layer that is in view; nothing orange in an empty corner."""
    cell, path, _html = pages["eur_pallet"]
    browser.open(path)
    data = browser.evaluate("codegenView.data")
    view = next(i for i, v in enumerate(data["views"]) if v["target"] == "kuka")
    moves = len(data["views"][view]["programs"][0]["runs"][0]["moves"])
    _state, _links, empty = _show(browser, "#target=kuka&program=0&m=1&labels=0")
    state, links, image = _show(browser, f"#target=kuka&program=0&m={moves}&labels=0")
    assert state["move"] == moves - 1 and state["joints"] is not None
    assert sum(_near(image, xy, is_arm) for xy in links) >= 4, "the arm's links are not orange on the screen"
    assert not any(is_arm(image.getpixel((x, y))) for x in range(5, 60) for y in range(100, 160))
    pallet = cell.sections["pallet"][0]
    top = [
        o
        for o in data["objects"]
        if o["role"] == "box" and o["label"].startswith(f"{pallet.name}: layer {pallet.layers} ")
    ]
    assert top
    faces = []
    for o in top:
        pose = np.reshape(o["pose"], (4, 4))
        faces.append(list(pose[:3, 3] + pose[:3, 2] * o["size"][2] / 2))
    on_screen = browser.evaluate(f"{json.dumps(faces)}.map(p => codegenView.project(p))")
    # in view: not behind the arm itself (its orange links or its dark joints, where the run ends above the pallet)
    seen = [xy for xy in on_screen if not _near(image, xy, lambda p: is_arm(p) or is_joint(p), radius=3)]
    carton = sum(_near(image, xy, is_box) for xy in seen)
    assert len(seen) >= 2 and carton >= 0.7 * len(seen), f"{carton} of {len(seen)} top boxes in view show their carton"
    assert sum(_near(empty, xy, is_box) for xy in on_screen) == 0, "the top layer is there before it is stacked"


def test_the_slider_moves_the_arm(pages, browser):
    """The demo cell on UR: the start and the work pose of station 1 are different pictures, the arm's orange where
    the page's state puts its links each time, and the joints are the move's at each whole position."""
    _cell, path, _html = pages["agv_machine_tending"]
    browser.open(path)
    run = browser.evaluate("codegenView.data.views[0].programs[0].runs[0]")
    first, first_links, first_image = _show(browser, "#target=ur&program=0&m=0&labels=0")
    later, later_links, later_image = _show(browser, "#target=ur&program=0&m=3&labels=0")
    assert first["joints"] == run["start"] and later["joints"] == run["moves"][2]["joints"]
    assert first["joints"] != later["joints"]
    changed = np.count_nonzero(np.any(np.asarray(first_image) != np.asarray(later_image), axis=2))
    assert changed > 2000, f"only {changed} pixels changed"
    for image, links in ((first_image, first_links), (later_image, later_links)):
        assert sum(_near(image, xy, is_arm) for xy in links) >= 4
    moved = [np.hypot(a[0] - b[0], a[1] - b[1]) for a, b in zip(first_links, later_links, strict=True)]
    assert max(moved) > 20  # the arm's drawing moved on the screen
    halfway, _links, _image = _show(browser, "#target=ur&program=0&m=2.5&labels=0")
    expected = (np.array(run["moves"][1]["joints"]) + np.array(run["moves"][2]["joints"])) / 2
    assert np.allclose(halfway["joints"], expected, atol=1e-9)


def test_a_target_without_an_arm_shows_the_tools_poses(pages, browser):
    """dtrans has no arm model: no joints, the TCP where the trace puts it (its black dot on the screen, at the
    highest pose of the cycle, where nothing hides it)."""
    _cell, path, _html = pages["testmat_pallet"]
    browser.open(path)
    view = browser.evaluate("codegenView.data.views.findIndex(v => v.target === 'dtrans')")
    run = browser.evaluate(f"codegenView.data.views[{view}].programs[0].runs[0]")
    highest = int(np.argmax([m["pose"][11] for m in run["moves"]]))
    state, links, image = _show(browser, f"#target=dtrans&program=0&m={highest + 1}&labels=0")
    assert state["joints"] is None and links == []
    assert np.allclose(state["tcp"], run["moves"][highest]["pose"], atol=1e-9)
    tcp = browser.evaluate(f"codegenView.project({json.dumps(state['tcp'][3:12:4])})")
    assert _near(image, tcp, lambda p: max(p) < 60), "the TCP's dot is not on the screen"
    assert browser.errors() == []


def test_a_cells_strings_stay_text_in_the_page(write_cell, browser, tmp_path):
    """A station named like markup: the page holds it as text (in the data, exactly), and no element comes of it."""
    name = 'lathe </script><script>alert(1)</script> "x" &amp;'
    text = (EXAMPLES_DIR / "agv_machine_tending.toml").read_text(encoding="utf-8")
    cell = load_cell(write_cell(text.replace('name = "lathe_1"', f"name = {json.dumps(name)}")))
    html = cell_page(cell, ["ur"])
    assert "<script>alert" not in html
    assert any(o["label"].startswith(f"{name}: ") for o in _data(html)["objects"])
    path = tmp_path / "page.html"
    path.write_text(html, encoding="utf-8")
    browser.open(path)
    assert browser.errors() == []
    assert browser.evaluate("document.querySelectorAll('script').length") == 3
    assert browser.evaluate("document.body.innerHTML.includes('<script>alert')") is False


@pytest.mark.parametrize("name", ["eur_pallet", "agv_machine_tending"])
def test_the_canvas_fills_the_window_and_the_framing_shows_every_object_whole(pages, browser, name):
    """The canvas took 80 % of the window's height; the framing looked at the objects' centres (at 0.8 of the
    distance that shows them), so a long fence or the pallet's far boxes could stand beyond the picture's edge."""
    _cell, path, _html = pages[name]
    browser.open(path)
    sizes = browser.evaluate(
        "(() => { const c = document.querySelector('#stage canvas').getBoundingClientRect();"
        " return [c.left, c.top, c.right, c.bottom, window.innerHeight,"
        " document.querySelector('header').offsetHeight]; })()"
    )
    left, top, right, bottom, height, header = sizes
    assert bottom - top >= height - header - 2, sizes
    corners = []
    for o in browser.evaluate("codegenView.data")["objects"]:
        if o["type"] != "box":
            continue
        pose, half = np.reshape(o["pose"], (4, 4)), np.asarray(o["size"]) / 2
        corners += [list(pose[:3, :3] @ (half * s) + pose[:3, 3]) for s in itertools.product((-1, 1), repeat=3)]
    assert corners
    shown = browser.evaluate(f"{json.dumps(corners)}.map(p => codegenView.project(p))")
    inside = [left <= x <= right and top <= y <= bottom for x, y, _z in shown]
    outside = [c for c, ok in zip(corners, inside, strict=True) if not ok]
    assert not outside, f"{len(outside)} of {len(corners)} corners off the picture, e.g. {outside[:3]}"


def is_current(pixel) -> bool:
    """The move the arm is on (#ffd000 as shaded): hue 40-60 deg, fully saturated."""
    h, s, v = _hsv(pixel)
    return 0.11 <= h <= 0.17 and s > 0.85 and v > 0.4


@pytest.mark.parametrize("fragment", ["m=3", "m=4.5"])
def test_the_move_the_arm_is_on_stands_out_over_the_path(pages, browser, fragment):
    """A long path was one colour: which move the arm is on could not be told from the others."""
    _cell, path, _html = pages["agv_machine_tending"]
    browser.open(path)
    state, _links, image = _show(browser, f"#target=ur&program=0&{fragment}&labels=0")
    assert state["segment"] is not None
    a, b = np.asarray(state["segment"][0]), np.asarray(state["segment"][1])
    along = [list(a + (b - a) * t) for t in (0.1, 0.2, 0.3)]  # away from the arm's tool, at the move's end or middle
    shown = browser.evaluate(f"{json.dumps(along)}.map(p => codegenView.project(p))")
    assert sum(_near(image, xy, is_current) for xy in shown) >= 2
    assert not any(is_current(image.getpixel((x, y))) for x in range(5, 60) for y in range(100, 160))
