"""Files the user names for output (--timings, pallet --svg) go through one door: what codegen did not write is left
alone, said before any work; --signal names an input the controller has; the catalogue counts its arms from 0."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main
from tests.plant.conftest import fake_verify, plant  # noqa: F401 (fixtures)


def test_a_timings_file_of_the_users_is_left_alone_before_any_cell_runs(plant, fake_verify, tmp_path):  # noqa: F811
    """--timings replaced any file, after the whole run."""
    mine = tmp_path / "notes.json"
    mine.write_text('{"mine": true}\n')
    result = CliRunner().invoke(main, ["verify", str(plant), "--timings", str(mine)])
    assert result.exit_code == 2, result.output
    assert f"--timings: {mine}: exists and was not written by codegen; left alone" in result.output
    assert fake_verify.calls == [] and mine.read_text() == '{"mine": true}\n'


def test_a_timings_file_is_written_then_replaced_by_the_next_run(plant, fake_verify, tmp_path):  # noqa: F811
    times = tmp_path / "times.json"
    for _ in range(2):
        result = CliRunner().invoke(main, ["verify", str(plant), "--timings", str(times)])
        assert result.exit_code == 0, result.output
        assert times.read_text().startswith('{\n  "command": "verify",\n  "plant": "')


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_a_timings_fifo_is_refused_at_once(plant, fake_verify, tmp_path):  # noqa: F811
    fifo = tmp_path / "times.json"
    os.mkfifo(fifo)
    result = CliRunner().invoke(main, ["verify", str(plant), "--timings", str(fifo)])
    assert result.exit_code == 2 and "not a regular file" in result.output, result.output
    assert fake_verify.calls == []


def test_pallet_pictures_leave_a_users_file_alone_and_write_none(tmp_path):
    """--svg replaced a file of the layer's name, whoever wrote it."""
    folder = tmp_path / "svg"
    folder.mkdir()
    (folder / "testmat_layer03.svg").write_text("my drawing\n")
    result = CliRunner().invoke(main, ["pallet", "--svg", str(folder)])
    assert result.exit_code == 2, result.output
    assert "testmat_layer03.svg: exists and was not written by codegen; left alone" in result.output
    assert sorted(p.name for p in folder.iterdir()) == ["testmat_layer03.svg"]  # none written before the refusal
    assert (folder / "testmat_layer03.svg").read_text() == "my drawing\n"


def test_pallet_pictures_replace_their_own(tmp_path):
    folder = tmp_path / "svg"
    for _ in range(2):
        result = CliRunner().invoke(main, ["pallet", "--svg", str(folder)])
        assert result.exit_code == 0, result.output
    assert len(list(folder.glob("testmat_layer*.svg"))) == 5 and not list(folder.glob(".*"))


@pytest.mark.parametrize(
    ("signal", "says"),
    [
        ("standard_digital_in[99]=1", "no input 99 on Universal Robots URScript"),
        ("standard_digital_in[-1]=1", "no input -1 on Universal Robots URScript"),
    ],
)
def test_a_signal_beyond_the_controllers_inputs_is_refused(tmp_path, signal, says):
    program = tmp_path / "p.script"
    program.write_text("def p():\n  textmsg(get_standard_digital_in(1))\nend\n")
    result = CliRunner().invoke(main, ["run", str(program), "--target", "ur", "--signal", signal])
    assert result.exit_code == 2 and says in result.output, result.output
    inside = CliRunner().invoke(main, ["run", str(program), "--target", "ur", "--signal", "standard_digital_in[7]=1"])
    assert inside.exit_code == 0, inside.output


def test_the_catalogue_counts_its_arms_from_0(tmp_path, monkeypatch):
    """arm[i + 1] where every other element path (station[0], pallet[0]) counts from 0."""
    from codegen.robot import arms

    text = arms.CATALOGUE.read_text(encoding="utf-8")
    first = text.index("\n[[arm]]\n") + 1
    second = text.index("\n[[arm]]\n", first) + 1
    copy = tmp_path / "catalogue.toml"
    copy.write_text(text[:second] + text[first:second] + text[second:], encoding="utf-8")  # arm 0 again, as arm 1
    monkeypatch.setattr(arms, "CATALOGUE", Path(copy))
    arms.catalogue.cache_clear()
    try:
        with pytest.raises(arms.ArmError, match=r"catalogue\.toml: arm\[1\]\.model: .* listed twice"):
            arms.catalogue()
    finally:
        monkeypatch.undo()
        arms.catalogue.cache_clear()
