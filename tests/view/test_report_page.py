"""verify's report as a page: the table per target and section, the error plots, the margins, the mismatches, and
the kept cases replayed in 3D beside the reference's poses (loaded in headless Chromium)."""

from __future__ import annotations

import html as htmlmod
import re
from dataclasses import replace

import numpy as np
import pytest
from support.programs import sources

from codegen.model.cell import DEMO_CELL, EXAMPLES_DIR, load_cell
from codegen.poses import POSE_FORMATS
from codegen.verify.engine import Options, verify_sources
from codegen.verify.programs import fresh_sources
from codegen.verify.report import Report
from codegen.view.report import report_page

TESTMAT = EXAMPLES_DIR / "pallets" / "testmat_pallet.toml"


def _report(cell, source_list, cases: int = 2) -> Report:
    rows, workers = verify_sources(cell, source_list, Options(cases, 0, 1, sweeps=False, keep_replays=True))
    return Report(cell.name, rows, 0, cases, 0.0, workers)


def _shorter_tool(cell):
    """The cell with its tool 10 mm shorter: programs made from it are 10 mm off the true cell's reference."""
    shorter = cell.robot.tool.tcp2flange @ np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, -10.0], [0, 0, 0, 1]])
    values = tuple(float(v) + 0.0 for v in POSE_FORMATS[cell.pose_format][2](shorter))
    tool = replace(cell.robot.tool, tcp=values, tcp2flange=shorter)
    return replace(cell, robot=replace(cell.robot, tool=tool))


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    cell = load_cell(DEMO_CELL)
    report = _report(cell, fresh_sources(cell, ["ur", "dtrans"]))
    path = tmp_path_factory.mktemp("report") / "demo.html"
    path.write_text(report_page(cell, report), encoding="utf-8")
    return cell, report, path


def test_the_demo_report_has_a_table_per_target_plots_and_margins(demo):
    _cell, report, path = demo
    html = path.read_text(encoding="utf-8")
    assert report.ok and "verify: all traces match the reference" in html
    assert html.count("<h2>target ur</h2>") == 1 and html.count("<h2>target dtrans</h2>") == 1
    for row in report.rows:
        assert f">{row.program}</td>" in html
        assert f"<td>{row.cases}</td>" in html
    assert html.count('<svg xmlns="http://www.w3.org/2000/svg"') == 4  # position and rotation, per target
    assert html.count("<polyline") >= 4
    ur = next(r for r in report.rows if r.target == "ur").arm.summary()
    assert f"<td>{ur['joint_margin_deg']:.1f}</td><td>{ur['wrist_margin_deg']:.1f}</td>" in html


def test_the_worst_cases_are_replayed_beside_the_reference(demo, browser):
    """In the browser: a view per target, each program's worst case (the largest position error) whose trace is the
    one verify kept, and the reference's poses each within that case's largest error of the trace's."""
    _cell, report, path = demo
    browser.open(path)
    assert browser.errors() == []
    views = browser.evaluate("codegenView.data.views")
    assert [v["target"] for v in views] == ["ur", "dtrans"]
    for view in views:
        rows = [r for r in report.rows if r.target == view["target"]]
        assert [p["label"].split(":")[0] for p in view["programs"]] == [r.program for r in rows]
        for row, program in zip(rows, view["programs"], strict=True):
            assert "worst case" in program["label"]
            (run,) = program["runs"]
            kept = row.worst
            assert kept.pos_max == max(row.pos_errors)  # the case with the row's largest position error
            assert run["what"] == kept.what
            assert [m["joints"] for m in run["moves"]] == [
                None if m.joints is None else [float(v) for v in m.joints] for m in kept.trace.moves
            ]
            trace = np.array([m["pose"] for m in run["moves"] if m["pose"] is not None])[:, [3, 7, 11]]
            reference = np.array([p for p in run["reference"] if p is not None])[:, [3, 7, 11]]
            assert len(reference) >= 3
            nearest = np.min(np.linalg.norm(reference[:, None] - trace[None], axis=2), axis=1)
            assert np.all(nearest <= kept.pos_max + 1e-5), nearest.max()


def test_a_mismatching_program_lists_its_mismatches_and_replays_one(tmp_path, browser):
    """The pallet program made for a tool 10 mm shorter, judged against the cell: every case mismatches; the page
    names each mismatch the row keeps, and replays one with its mismatch."""
    cell = load_cell(TESTMAT)
    report = _report(cell, sources(_shorter_tool(cell), "ur")[:1], cases=1)  # the socket form (the node form alike)
    (row,) = report.rows
    assert row.mismatches > 0 and row.failed is not None and row.worst is None
    path = tmp_path / "bad.html"
    path.write_text(report_page(cell, report), encoding="utf-8")
    html = path.read_text(encoding="utf-8")
    assert "verify: MISMATCHES" in html
    items = {htmlmod.unescape(item) for item in re.findall(r"<li>(.*?)</li>", html, flags=re.S)}
    for line in row.first_mismatches:  # compared as text: how a quote is escaped is the template engine's choice
        assert line in items
    if row.mismatches > len(row.first_mismatches):
        assert f"and {row.mismatches - len(row.first_mismatches)} more" in html
    browser.open(path)
    assert browser.errors() == []
    (program,) = browser.evaluate("codegenView.data.views[0].programs")
    assert "mismatch" in program["label"] and program["problem"] == row.failed.problem
    assert len(program["runs"][0]["moves"]) == len(row.failed.trace.moves)
