"""`codegen view` and `codegen verify --html` on the command line: the page written whole, a file codegen did not
write left alone (exit 2, before any work), bad targets named."""

from __future__ import annotations

import json

from click.testing import CliRunner

from codegen.cli import main
from codegen.model.cell import EXAMPLES_DIR

LASER = EXAMPLES_DIR / "laser" / "laser_tcp.toml"
TESTMAT = EXAMPLES_DIR / "pallets" / "testmat_pallet.toml"


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_view_writes_the_page_and_replaces_only_its_own(tmp_path):
    out = tmp_path / "pages" / "laser.html"
    first = invoke("view", LASER, "--target", "ur", "--out", out)
    assert first.exit_code == 0, first.stderr
    assert f"wrote {out}" in first.stdout
    html = out.read_text(encoding="utf-8")
    assert html.startswith("<!doctype html>") and '<meta name="generator" content="codegen view' in html
    assert [p.name for p in out.parent.iterdir()] == ["laser.html"]  # no temporary file left
    again = invoke("view", LASER, "--target", "ur", "--out", out)
    assert again.exit_code == 0, again.stderr


def test_view_leaves_a_file_it_did_not_write_alone(tmp_path):
    mine = tmp_path / "notes.html"
    mine.write_text("<p>my notes</p>", encoding="utf-8")
    result = invoke("view", LASER, "--target", "ur", "--out", mine)
    assert result.exit_code == 2
    assert f"{mine}: exists and was not written by codegen" in result.stderr
    assert "Traceback" not in result.stderr
    assert mine.read_text(encoding="utf-8") == "<p>my notes</p>"
    folder = invoke("view", LASER, "--target", "ur", "--out", tmp_path)
    assert folder.exit_code == 2 and "is a directory" in folder.stderr


def test_view_names_a_target_the_cell_does_not_have(tmp_path):
    result = invoke("view", LASER, "--target", "dtrans", "--out", tmp_path / "x.html")
    assert result.exit_code == 2
    assert "--target dtrans: not a target of cell laser_tcp (ur, kuka, abb)" in result.stderr
    assert not (tmp_path / "x.html").exists()


def test_view_writes_cell_html_by_default(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = invoke("view", LASER, "--target", "abb")
    assert result.exit_code == 0, result.stderr
    assert (tmp_path / "laser_tcp.html").is_file()


def test_verify_html_writes_the_report_and_keeps_the_json(tmp_path, no_sweeps):
    """The pallet cell on UR: the page beside the JSON report, whose keys are those of a run without --html."""
    out = tmp_path / "report.html"
    args = ("verify", TESTMAT, "--target", "ur", "--cases", "1", "--jobs", "1", "--json")
    plain = invoke(*args)
    paged = invoke(*args, "--html", out)
    assert plain.exit_code == 0 and paged.exit_code == 0, paged.stderr
    assert f"wrote {out}" in paged.stderr
    before, after = json.loads(plain.stdout), json.loads(paged.stdout)
    assert before.keys() == after.keys()
    assert [p.keys() for p in before["programs"]] == [p.keys() for p in after["programs"]]
    html = out.read_text(encoding="utf-8")
    assert "verify: all traces match the reference" in html and "pal_testmat" in html


def test_verify_html_leaves_a_file_it_did_not_write_alone_before_verifying(tmp_path):
    mine = tmp_path / "report.html"
    mine.write_text("mine", encoding="utf-8")
    result = invoke("verify", TESTMAT, "--target", "ur", "--cases", "1", "--html", mine)
    assert result.exit_code == 2 and "exists and was not written by codegen" in result.stderr
    assert "verify:" not in result.stdout  # nothing ran
    assert mine.read_text(encoding="utf-8") == "mine"
