"""A KRL program file given alone brings its .dat and the data lists beside it that declare names it uses, so
that check, run and verify read the same files."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from codegen.cli import main
from tests.dialects.krl.helpers import KRL

CELL = "DEF CELL()\nSTACKED = STACKED + 1\nMsgNotify(\"stacked\")\nEND\n"
CELL_DAT = "DEFDAT CELL\nDECL INT UNUSED_HERE=0\nENDDAT\n"
COUNTERS = "DEFDAT CELL_COUNT PUBLIC\nDECL GLOBAL INT STACKED=0\nENDDAT\n"
OTHER_LIST = "DEFDAT SPARE PUBLIC\nDECL GLOBAL INT SPARE_N=0\nENDDAT\n"


def folder(tmp_path: Path) -> Path:
    for name, text in {
        "cell.src": CELL, "cell.dat": CELL_DAT, "cell_count.dat": COUNTERS, "spare.dat": OTHER_LIST,
        "other.src": "DEF OTHER()\nEND\n", "other.dat": "DEFDAT OTHER\nDECL GLOBAL INT STACKED=5\nENDDAT\n",
    }.items():  # fmt: skip
        (tmp_path / name).write_text(text)
    return tmp_path / "cell.src"


def test_a_program_brings_its_dat_and_the_data_lists_that_declare_what_it_uses(tmp_path):
    program = folder(tmp_path)
    assert [p.name for p in KRL.beside(program)] == ["cell.dat", "cell_count.dat"]  # not spare.dat, not other.dat


def test_check_and_run_of_the_program_file_alone_read_its_data_lists(tmp_path):
    program = folder(tmp_path)
    checked = CliRunner().invoke(main, ["check", str(program)])
    assert checked.exit_code == 0, checked.output
    assert "3 files" in checked.output
    ran = CliRunner().invoke(main, ["run", str(program)])
    assert ran.exit_code == 0, ran.output
    assert "message: stacked" in ran.output


def test_a_data_list_that_does_not_parse_comes_along_and_is_named_at_its_line(tmp_path):
    program = folder(tmp_path)
    (tmp_path / "cell_count.dat").write_text("DEFDAT CELL_COUNT PUBLIC\nDECL GLOBAL INT STACKED = = 0\nENDDAT\n")
    checked = CliRunner().invoke(main, ["check", str(program)])
    assert checked.exit_code == 2
    assert "cell_count.dat:2:" in checked.output


def test_a_program_is_read_with_the_data_lists_it_uses_among_another_programs_files():
    """The rule of the folder on disk, over files in memory (verify's fresh programs): a .dat without a .src of its
    own that declares a name the program uses; not another program's own .dat, not an unused list."""
    from codegen.dialects.core.files import SourceFile

    program = SourceFile("cell.src", CELL)
    others = [
        SourceFile("cell_count.dat", COUNTERS),
        SourceFile("spare.dat", OTHER_LIST),
        SourceFile("other.src", "DEF OTHER()\nEND\n"),
        SourceFile("other.dat", "DEFDAT OTHER\nDECL GLOBAL INT STACKED=5\nENDDAT\n"),
    ]
    assert [f.name for f in KRL.shared_among(program, others)] == ["cell_count.dat"]


def test_a_name_of_a_data_list_not_beside_the_program_names_the_files_read(tmp_path):
    program = folder(tmp_path)
    (tmp_path / "cell_count.dat").unlink()
    for command in ("check", "run"):
        result = CliRunner().invoke(main, [command, str(program)])
        assert result.exit_code == 2, result.output
        assert "cell.src:2:" in result.output and "undefined variable STACKED" in result.output, result.output
        assert "declared in none of the files read (cell.src, cell.dat)" in result.output, result.output
        assert "DEFDAT ... PUBLIC" in result.output
