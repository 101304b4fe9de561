"""The KUKA pallet programs of one arm share their holds flags through their GLOBAL count data lists: check, run and
verify read the other programs' count files with a program, and a program without them is refused by name."""

from __future__ import annotations

import shutil
from pathlib import Path

from click.testing import CliRunner
from support.programs import sources

from codegen.cli import main
from codegen.model.cell import load_cell

ROOT = Path(__file__).resolve().parents[2]
EUR = ROOT / "codegen" / "examples" / "pallets" / "eur_pallet.toml"
GENERATED = ROOT / "generated" / "eur_pallet" / "kuka"


def _names(source) -> list[str]:
    return [Path(f.name).name for f in source.files]


def test_verify_reads_a_kuka_pallet_program_with_the_other_pallets_count_files():
    by_program = {s.ident: _names(s) for s in sources(load_cell(EUR), "kuka", "pallet")}
    assert by_program["pal_eur"] == ["pal_eur.src", "pal_eur.dat", "pal_eur_count.dat", "pal_eur_in_count.dat"]
    assert by_program["pal_eur_in"] == ["pal_eur_in.src", "pal_eur_in.dat", "pal_eur_in_count.dat", "pal_eur_count.dat"]


def test_an_abb_task_reads_only_its_own_files():
    for source in sources(load_cell(EUR), "abb", "pallet"):
        assert not any(name.endswith("_count.dat") for name in _names(source)), _names(source)


def test_the_generated_program_is_checked_with_the_count_files_beside_it():
    result = CliRunner().invoke(main, ["check", str(GENERATED / "pal_eur.src")])
    assert result.exit_code == 0, result.output
    assert "4 files" in result.output, result.output


def test_a_program_copied_without_the_other_count_file_is_refused_by_name(tmp_path):
    for name in ("pal_eur.src", "pal_eur.dat", "pal_eur_count.dat"):
        shutil.copy(GENERATED / name, tmp_path / name)
    checked = CliRunner().invoke(main, ["check", str(tmp_path / "pal_eur.src")])
    assert checked.exit_code == 2, checked.output
    assert "undefined variable PAL_EUR_IN_HOLDS, declared in none of the files read" in checked.output
    verified = CliRunner().invoke(main, ["verify", str(EUR), str(tmp_path / "pal_eur.src"), "--cases", "1"])
    assert verified.exit_code == 2, verified.output
    assert "PAL_EUR_IN_HOLDS" in verified.output and "Traceback" not in verified.output, verified.output


def test_the_language_server_reads_the_program_with_the_same_files():
    from codegen.lsp.documents import program_of

    program = program_of((GENERATED / "pal_eur.src").resolve(), {})
    assert [Path(f.name).name for f in program.files] == [
        "pal_eur.src",
        "pal_eur.dat",
        "pal_eur_count.dat",
        "pal_eur_in_count.dat",
    ]
