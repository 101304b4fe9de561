"""`codegen verify PLANT`: one table, stored results reused while nothing they depend on changes, bad cells reported
beside the others (verify_cell stood in for: these tests are about the plant, not the interpreter)."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from codegen.cli import main


def _verify(plant: Path, *args: str):
    result = CliRunner().invoke(main, ["verify", str(plant), "--cases", "2", "--json", *args])
    return result.exit_code, (json.loads(result.output) if result.output.startswith("{") else result.output)


def _results(report: dict) -> dict[str, str]:
    return {row["cell"]: row["result"] for row in report["rows"]}


def test_a_second_run_reports_every_cell_cached_with_its_figures(plant, fake_verify):
    code, first = _verify(plant)
    assert code == 0 and _results(first) == {"a/tray.toml": "ok", "b/gate.toml": "ok"}
    assert sorted(fake_verify.calls) == ["tray_dtrans", "warehouse_dtrans"]
    code, second = _verify(plant)
    assert code == 0 and _results(second) == {"a/tray.toml": "cached", "b/gate.toml": "cached"}
    assert len(fake_verify.calls) == 2  # nothing verified again
    assert [r["cases"] for r in second["rows"]] == [r["cases"] for r in first["rows"]]
    assert [c["data"] for c in second["cells"]] == [c["data"] for c in first["cells"]]
    assert (plant / ".codegen-cache" / "verify").is_dir()


def test_a_changed_cell_file_is_verified_again_alone(plant, fake_verify):
    _verify(plant)
    gate = plant / "b" / "gate.toml"
    gate.write_text(gate.read_text() + "\n# a comment is a change of the file\n")
    code, report = _verify(plant)
    assert code == 0 and _results(report) == {"a/tray.toml": "cached", "b/gate.toml": "ok"}
    assert fake_verify.calls[2:] == ["warehouse_dtrans"]


def test_other_options_are_other_entries(plant, fake_verify):
    _verify(plant)
    _, report = _verify(plant, "--seed", "1")
    assert set(_results(report).values()) == {"ok"}
    _, report = _verify(plant, "--no-cache")
    assert set(_results(report).values()) == {"ok"} and len(fake_verify.calls) == 6


def test_a_corrupt_entry_is_verified_again_and_rewritten(plant, fake_verify):
    _verify(plant)
    entries = sorted((plant / ".codegen-cache").rglob("*.json"))
    assert len(entries) == 2
    for entry in entries:
        entry.write_bytes(entry.read_bytes()[:40])
    code, report = _verify(plant)
    assert code == 0 and set(_results(report).values()) == {"ok"} and len(fake_verify.calls) == 4
    assert all(any("was unreadable" in note for note in cell["notes"]) for cell in report["cells"])
    _, report = _verify(plant)
    assert set(_results(report).values()) == {"cached"}


def test_a_failing_result_is_cached_and_still_fails(plant, fake_verify):
    fake_verify.failing.add("warehouse_dtrans")
    code, report = _verify(plant)
    assert code == 1 and _results(report)["b/gate.toml"] == "mismatch"
    code, report = _verify(plant)
    assert code == 1 and _results(report) == {"a/tray.toml": "cached", "b/gate.toml": "cached mismatch"}
    assert len(fake_verify.calls) == 2


def test_a_bad_cell_is_a_row_and_the_others_run(plant, fake_verify):
    (plant / "c.toml").write_text('[cell]\nname = "x"\ntargets = ["nowhere"]\n')
    code, report = _verify(plant)
    rows = _results(report)
    assert code == 2 and rows == {"a/tray.toml": "ok", "b/gate.toml": "ok", "c.toml": "error"}
    message = next(r["message"] for r in report["rows"] if r["cell"] == "c.toml")
    assert str(plant / "c.toml") in message and "cell.targets" in message


def test_the_text_table_and_the_cache_folder_option(plant, fake_verify, tmp_path):
    store = tmp_path / "ci-cache"
    result = CliRunner().invoke(main, ["verify", str(plant), "--cases", "2", "--cache-dir", str(store)])
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert lines[1].split() == ["cell", "target", "kind", "cases", "result", "time"]
    assert [line.split()[0] for line in lines[2:4]] == ["a/tray.toml", "b/gate.toml"]
    assert lines[-1].startswith("2 rows: 2 ok;")
    assert len(list(store.rglob("*.json"))) == 2 and not (plant / ".codegen-cache").exists()


def test_the_plants_defaults_apply_unless_an_option_is_given(plant, fake_verify):
    (plant / "codegen.toml").write_text('[plant]\ncases = 7\nseed = 3\ncells = ["a/tray.toml"]\n')
    _, report = _verify(plant / "codegen.toml")
    assert report["cells"][0]["data"]["random_per_station"] == 2  # --cases 2 given
    assert report["cells"][0]["data"]["seed"] == 3
    result = CliRunner().invoke(main, ["verify", str(plant), "--json", "--no-cache"])
    assert json.loads(result.output)["cells"][0]["data"]["random_per_station"] == 7


def test_a_verified_cells_time_is_its_own_not_the_batchs(plant, fake_verify, tmp_path):
    """The cells are verified together: a row's time is its report's wall time, in the table and in --timings."""
    fake_verify.walls = {"tray_dtrans": 3.1, "warehouse_dtrans": 32.9}
    timings = tmp_path / "times.json"
    result = CliRunner().invoke(main, ["verify", str(plant), "--cases", "2", "--no-cache", "--timings", str(timings)])
    assert result.exit_code == 0, result.output
    rows = {line.split()[0]: line for line in result.output.splitlines() if line.startswith(("a/", "b/"))}
    assert rows["a/tray.toml"].endswith(" 3.1 s") and rows["b/gate.toml"].endswith(" 32.9 s"), result.output
    seconds = [cell["rows"][0]["seconds"] for cell in json.loads(timings.read_text())["cells"]]
    assert seconds == [3.1, 32.9]
