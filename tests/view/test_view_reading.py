"""The page read as a person reads it: labels that would overlap on the screen are hidden (the first kept), and the
numbers of a run's reading are rounded for reading while the data keeps every digit."""

from __future__ import annotations

import re

import pytest

from codegen.model.cell import EXAMPLES_DIR, load_cell
from codegen.view.page import cell_page


@pytest.fixture(scope="module")
def agv_page(tmp_path_factory):
    """The demo cell's page for its UR: its solids and five stations' marks labelled, two lathes' and two mills'
    marks side by side (their labels meet on the screen from the page's first view)."""
    cell = load_cell(EXAMPLES_DIR / "agv_machine_tending.toml")
    path = tmp_path_factory.mktemp("page") / "agv.html"
    path.write_text(cell_page(cell, ["ur"]), encoding="utf-8")
    return path


def _overlap(a, b) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def test_overlapping_labels_are_hidden_the_first_kept(agv_page, browser):
    browser.open(agv_page, "#target=ur&program=0&m=0")
    assert browser.errors() == []
    labels = browser.evaluate("codegenView.labels()")
    shown = [label for label in labels if label["shown"]]
    assert len(labels) >= 7 and 0 < len(shown) < len(labels)
    for i, a in enumerate(shown):  # no two shown labels overlap on the screen
        for b in shown[i + 1 :]:
            assert not _overlap(a["rect"], b["rect"]), (a["text"], b["text"])
    for k, label in enumerate(labels):  # each hidden one lies under a shown one before it
        if label["shown"] or label["rect"] is None:
            continue
        assert any(o["shown"] and _overlap(o["rect"], label["rect"]) for o in labels[:k]), label["text"]
    # a station's mark comes before its poses: the marks are the labels kept
    assert [label["text"] for label in shown if label["text"].endswith(": mark")]
    # the labels off: none shown
    browser.evaluate("document.getElementById('labels').click()")
    assert not any(label["shown"] for label in browser.evaluate("codegenView.labels()"))


def test_a_runs_reading_is_shown_rounded_and_kept_whole_in_the_data(agv_page, browser, tmp_path):
    page = tmp_path / "again.html"  # another file: the browser loads it anew
    page.write_text(agv_page.read_text(encoding="utf-8"), encoding="utf-8")
    browser.open(page, "#target=ur&program=0&m=1")
    what = browser.evaluate("codegenView.data.views[0].programs[0].runs[0].what")
    assert re.search(r"\d+\.\d{6}", what), what  # the data: every digit the case has
    info = browser.evaluate("document.getElementById('info').textContent")
    assert "reading (" in info
    assert not re.search(r"\d\.\d{3,}", info.split("clock")[0]), info  # shown to 0.01 mm and deg
    digits = [float(v) for v in re.findall(r"-?\d+\.\d+", what.split("reading", 1)[1])]
    shown = [float(v) for v in re.findall(r"-?\d+\.\d+", info.split("reading", 1)[1].split(")")[0])]
    assert shown == [round(v, 2) + 0.0 for v in digits]
    assert "-0.00" not in info
