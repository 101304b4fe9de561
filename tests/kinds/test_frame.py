"""Frame correction with closed-loop refinement (source 001): cell rules, reference loop, programs."""

from __future__ import annotations

from pathlib import Path

import pytest
from support import stations

from codegen.controllers import get_target, target_names
from codegen.kinds.station.modes.frame import NOT_CONVERGED, FrameCase, expected_frame_trace
from codegen.kinds.station.section import section_of, stations_of, with_section
from codegen.model.cell import CellError, load_cell
from codegen.render import render
from codegen.sim.camera import CameraModel

BENCH = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "thermometer_bench.toml"


@pytest.fixture(scope="module")
def bench():
    return load_cell(BENCH)


def test_bench_cell_loads(bench):
    station = stations_of(bench)[0]
    assert station.mode == "frame" and station.spec.frame is not None and station.spec.photo is not None
    assert section_of(bench).handeye is not None and bench.sections["station"].settings["frame"].max_iterations == 10


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda t: t.replace("[cell.camera.handeye]", "[cell.camera.unused]"), "cell.camera.unused: unknown key"),
        (
            lambda t: t[: t.index("[cell.camera.handeye]")] + t[t.index("[cell.limits]") :],
            "station[0].mode: frame mode reads the camera in pixels and needs [cell.camera.handeye]",
        ),
        (
            lambda t: t.replace('mode = "frame"', 'mode = "frame"\nmark = [1.0, 2.0, 3.0]'),
            'station[0].mark: only point stations (mode = "point") have this key',
        ),
        (
            lambda t: t.replace('mode = "frame"', 'mode = "frames"'),
            "station[0].mode: expected one of 'point', 'frame' (the station's program kind), got 'frames'",
        ),
        (lambda t: t.replace("photo = [0.0, 0.0, 180.0, 0.0, 0.0, 180.0]", ""), "station[0].photo: missing"),
        (
            lambda t: t.replace(
                "mark = [380.0, -310.0, -1.2]", "mark = [380.0, -310.0, -1.2]\nphoto = [0, 0, 0, 0, 0, 0]"
            ),
            'station[1].photo: only frame stations (mode = "frame")',
        ),
        (lambda t: t.replace("max_iterations = 10", "max_iterations = 0"), "cell.refine.max_iterations"),
        (  # 4 x 0.1 px at the bench's 0.0172 mm/px: the loop would halt on the camera's noise
            lambda t: t.replace("tolerance_mm = 0.02", "tolerance_mm = 0.006"),
            "cell.refine.tolerance_mm: 0.006 mm is finer than the camera resolves",
        ),
    ],
)
def test_frame_cell_errors(tmp_path, change, message):
    path = tmp_path / "bench.toml"
    path.write_text(change(BENCH.read_text()), encoding="utf-8")
    with pytest.raises(CellError) as info:
        load_cell(path)
    assert message in str(info.value)


def test_reference_loop_converges_and_halts(bench):
    exact = expected_frame_trace(bench, FrameCase(1, 30.0, -40.0, 12.0, CameraModel()))
    # one correcting photo, one confirming photo; the image's per-axis scale (0.0170 and 0.0172 mm/px)
    # turns a 12 deg turn into 11.86 deg in the image's axes, so one more photo corrects the rest
    assert exact.status == "ok" and exact.detail.iterations == 3
    assert exact.detail.residuals[0][1] == pytest.approx(11.864, abs=1e-3)
    scaled = expected_frame_trace(bench, FrameCase(1, 30.0, -40.0, 12.0, CameraModel(scale_error=0.03)))
    assert scaled.status == "ok" and 3 <= scaled.detail.iterations <= 5
    weak = expected_frame_trace(bench, FrameCase(1, 30.0, -40.0, 12.0, CameraModel(scale_error=9.0)))
    assert weak.status == "halt" and weak.reason == NOT_CONVERGED and weak.detail.iterations == 10
    diverging = expected_frame_trace(bench, FrameCase(1, 30.0, -40.0, 12.0, CameraModel(rotation_error_deg=80)))
    assert diverging.status == "halt"


@pytest.mark.parametrize("target", target_names())
def test_frame_mode_verifies(bench, target):
    cases = stations.build_cases(bench, 12, 5)
    report = stations.verify(bench, stations.source(bench, target), cases)
    assert report.mismatches == 0, report.first_mismatches
    stats = report.figures.modes["frame"]
    assert stats.photos and max(stats.photos) >= 3  # hand-eye errors need more than two photos
    assert max(stats.errors_mm) < 0.03
    assert report.categories["frame_camera_too_weak"] == 4 and report.categories["frame_camera_diverges"] == 4


def _source_sign_printed(dialect: str):
    """derived.printed with the refinement update printed from source 001's R(-alpha), by the
    dialect's own printer (the derivation's frame_update(-1), the readable names of the cache)."""
    import sympy as sp

    from codegen import derived
    from codegen.dialects import get_dialect
    from codegen.kinds.station import derivation

    printer = get_dialect(dialect).printer()
    names = {sp.cos(derivation.alpha): sp.Symbol("cos_alpha"), sp.sin(derivation.alpha): sp.Symbol("sin_alpha")}
    printed_d, _ = derivation.frame_update(-1)
    pairs = zip(("new_dx", "new_dy"), printed_d, strict=True)
    outputs = {name: printer.doprint(expr.subs(names)) for name, expr in pairs}
    original = derived.printed

    def printed(name: str, block: str) -> dict:
        code = original(name, block)
        return {**code, "outputs": outputs} if (name, block) == (dialect, "refine") else code

    return printed


@pytest.mark.parametrize("target", target_names())
def test_source_update_sign_fails_verify(bench, target, monkeypatch):
    from codegen import derived

    dialect = get_target(target).dialect
    right = stations.files(bench, target)
    monkeypatch.setattr(derived, "printed", _source_sign_printed(dialect))
    text, dat = stations.files(bench, target)
    monkeypatch.undo()
    assert text != right[0]
    program = stations.source(bench, target, text, dat)
    cases = [c for c in stations.build_cases(bench, 12, 6) if c.category.startswith("frame_handeye")]
    report = stations.verify(bench, program, cases)
    assert report.mismatches > 0


def test_dtrans_needs_a_level_frame(tmp_path):
    from codegen.emit import EmitError

    path = tmp_path / "tilted.toml"
    path.write_text(
        BENCH.read_text().replace("[560.0, 150.0, 240.0, 30.0, 0.0, 0.0]", "[560.0, 150.0, 240.0, 30.0, 5.0, 0.0]"),
        encoding="utf-8",
    )
    tilted = load_cell(path)
    with pytest.raises(EmitError, match="frame must be level"):
        render(tilted, ["dtrans"])
    report = stations.verify(tilted, stations.source(tilted, "kuka"), stations.build_cases(tilted, 8, 2))
    assert report.mismatches == 0  # KRL composes a tilted frame with `:`


def test_rapidchecker_accepts_frame_module(tmp_path, bench):
    from rapidcheck import rapidchecker

    (f,) = render(bench, ["abb"])
    proc = rapidchecker(f.text, tmp_path / "bench.mod")
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_run_without_camera_says_so():
    from click.testing import CliRunner

    from codegen.cli import main

    program = Path(__file__).resolve().parents[2] / "generated" / "thermometer_bench" / "kuka" / "thermometer_bench.src"
    result = CliRunner().invoke(main, ["run", str(program), "--input", "VIS_STATION=1"])
    assert result.exit_code == 1
    assert "no camera is attached" in result.output


def test_correct_refuses_a_frame_station():
    from click.testing import CliRunner

    from codegen.cli import main

    result = CliRunner().invoke(main, ["correct", str(BENCH), "--station", "1", "--mark", "1,2,3"])
    assert result.exit_code == 2 and "is a frame station" in result.output


def test_kuka_base_data(tmp_path):
    text = BENCH.read_text().replace('mode = "frame"', 'mode = "frame"\nbase_data = 3')
    path = tmp_path / "bench.toml"
    path.write_text(text, encoding="utf-8")
    cell = load_cell(path)
    assert stations_of(cell)[0].spec.base_data == 3
    src = next(f for f in render(cell, ["kuka"]) if f.relpath.endswith(".src"))
    assert "$BASE = BASE_DATA[3] : OFFSET" in src.text
    report = stations.verify(cell, stations.source(cell, "kuka"), stations.build_cases(cell, 8, 3))
    assert report.mismatches == 0, report.first_mismatches
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("base_data = 3", "base_data = 40"), encoding="utf-8")
    with pytest.raises(CellError, match=r"station\[0\]\.base_data: target kuka stores bases 1\.\.32, got 40"):
        load_cell(bad)


# The unknown-id sweep (every id of the barcode range) is tested on every target in target_base.py;
# these frame-kind tests leave it out (sweep=False).
def test_a_cell_of_frame_stations_only(tmp_path):
    """A cell of one kind carries only that kind's interface, helpers and data, and verifies."""
    text = BENCH.read_text()
    path = tmp_path / "frames.toml"
    second = text.rindex("[[station]]", 0, text.index("\nid = 2\n"))  # the point station's table and what follows
    path.write_text(text[:second], encoding="utf-8")
    cell = load_cell(path)
    assert {s.mode for s in stations_of(cell)} == {"frame"}
    for target in target_names():
        point_inputs = [v for k, v in get_target(target).program["inputs"].items() if k != "station"]
        for f in render(cell, [target]):
            for name in point_inputs:
                assert name.split("[")[0] not in f.text, (target, name)
        report = stations.verify(cell, stations.source(cell, target), stations.build_cases(cell, 8, 1))
        assert report.mismatches == 0, report.first_mismatches


@pytest.mark.parametrize("target", target_names())
def test_a_cell_whose_angle_sign_contradicts_its_camera_fails_verify(bench, target):
    """The simulated camera knows nothing of the cell's angle_sign: it reports the mark's turn in its
    image's axes. Programs made from a cell with the other sign, verified against that same cell,
    fail (its own reference agrees with them, the camera does not)."""

    wrong = with_section(bench, angle_sign=-section_of(bench).angle_sign)  # a cell the loader would refuse
    report = stations.verify(wrong, stations.source(wrong, target), stations.build_cases(wrong, 12, 5))
    assert report.mismatches > 0
    assert any("angle_sign +1 and the camera's image" in m for m in report.first_mismatches)
    right = stations.verify(bench, stations.source(bench, target), stations.build_cases(bench, 12, 5))
    assert right.mismatches == 0, right.first_mismatches


def test_a_hand_eye_map_that_overflows_is_refused(tmp_path):
    import re

    path = tmp_path / "bench.toml"
    huge = "pixel_to_mm = [[1e200, 0.0, 1.0], [0.0, -1e200, 2.0]]"
    path.write_text(re.sub(r"pixel_to_mm = .*", huge, BENCH.read_text()), encoding="utf-8")
    with pytest.raises(
        CellError, match=r"cell\.camera\.handeye\.pixel_to_mm\[0\]\[0\]: must be in \[-100000, 100000\]"
    ):
        load_cell(path)


def test_a_hand_eye_map_that_cannot_be_inverted_is_refused(tmp_path):
    import re

    path = tmp_path / "bench.toml"
    singular = "pixel_to_mm = [[1.0, 2.0, 1.0], [2.0, 4.0, 2.0]]"
    path.write_text(re.sub(r"pixel_to_mm = .*", singular, BENCH.read_text()), encoding="utf-8")
    with pytest.raises(CellError, match=r"cell\.camera\.handeye\.pixel_to_mm: the 2x2 part is singular"):
        load_cell(path)
