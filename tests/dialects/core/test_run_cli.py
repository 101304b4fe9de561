"""codegen run: programs of several files or a folder, limits that end an endless program cleanly and keep
its trace, a stop without a message said plainly, and no Python names in any message."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main

REPO = Path(__file__).resolve().parents[3]
KUKA = REPO / "generated" / "agv_machine_tending" / "kuka"
LOOP = """def loop():
  set_tcp(p[0, 0, 0.1, 0, 0, 0])
  while True:
    movel(p[0.5, 0.1, 0.4, 0, 3.0, 0], v=0.1)
    set_standard_digital_out(1, True)
    movel(p[0.5, 0.2, 0.4, 0, 3.0, 0], v=0.1)
    set_standard_digital_out(1, False)
  end
end
"""


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


@pytest.fixture
def loop(tmp_path) -> Path:
    path = tmp_path / "loop.script"
    path.write_text(LOOP)
    return path


def test_max_moves_ends_an_endless_program_and_keeps_its_trace(loop):
    result = invoke("run", loop, "--max-moves", "3")
    assert result.exit_code == 0, result.output
    assert result.output.count("linear (line") == 3
    assert "output (line 5): standard_digital_out[1] = on" in result.output
    assert result.output.rstrip().splitlines()[-1].startswith("ended: 3 moves made (the run's limit of moves)")
    data = json.loads(invoke("run", loop, "--max-moves", "3", "--json").output)
    assert len(data["moves"]) == 3 and data["ended"].startswith("3 moves made") and data["error"] is None
    assert [o["value"] for o in data["outputs"]] == [True, False]


def test_max_seconds_ends_the_run_on_the_programs_clock(loop):
    data = json.loads(invoke("run", loop, "--max-seconds", "5", "--json").output)
    assert data["clock_s"] >= 5.0 and "passed 5 s" in data["ended"]
    assert 5 <= len(data["moves"]) <= 7  # 1 s a move (0.1 m at 0.1 m/s), the first from an unknown pose


def test_a_step_limit_keeps_what_ran_and_says_why(loop):
    text = invoke("run", loop, "--step-limit", "40")
    assert text.exit_code == 1 and text.output.count("linear (line") > 5
    assert "step limit 40 reached" in text.output
    result = invoke("run", loop, "--step-limit", "40", "--json")
    data = json.loads(result.stdout)
    assert result.exit_code == 1 and len(data["moves"]) > 5 and "step limit 40" in data["error"]
    assert "--max-moves" in data["ended"]


def test_a_stop_without_a_message_says_so(tmp_path):
    path = tmp_path / "stop.script"
    path.write_text("def stop():\n  halt\nend\n")
    result = invoke("run", path)
    assert result.exit_code == 0 and "HALT: the program stopped without a message" in result.output
    assert "None" not in result.output
    assert json.loads(invoke("run", path, "--json").output)["halt_message"] is None


def test_a_folder_or_a_program_with_its_data_file(tmp_path):
    folder = tmp_path / "cell"
    folder.mkdir()
    (folder / "main.script").write_text(LOOP)
    result = invoke("run", folder, "--max-moves", "2")
    assert result.exit_code == 0 and result.output.count("linear (line") == 2, result.output
    (folder / "other.script").write_text(LOOP)
    two = invoke("run", folder)
    assert two.exit_code == 2 and "make 2 programs" in two.output
    inputs = ["VIS_STATION=1", "VIS_X=612.4", "VIS_Y=-285", "VIS_THETA=1.8"]
    both = invoke(
        "run",
        *(KUKA / f"agv_machine_tending{suffix}" for suffix in (".src", ".dat", ".xml")),  # .xml: the channel's
        *(f"--input={i}" for i in inputs),
    )
    assert both.exit_code == 0 and "738.5000 -112.3000 305.2000" in both.output, both.output


def test_files_of_several_languages_need_a_target(tmp_path, loop):
    other = tmp_path / "x.prg"
    other.write_text("Double a = 1\n")
    result = invoke("run", loop, other)
    assert result.exit_code == 2 and "files of several languages" in result.output


# Programs that fail in many ways: no message may name a Python type, module or internal (issue 29).
PYTHON_WORDS = re.compile(
    r"NoneType|numpy|float32|float64|in \?|Traceback|<class|object|int\(\)|float\(\)|__|ufunc|dtype"
    r"|str'|'int'|list index"
)
BAD_UR = [
    'x = 1 + "a"',
    'x = "a" - 2',
    'x = -"a"',
    'x = [1, 2] * "b"',
    "x = p[0, 0, 0, 0, 0, 0] + 1",
    "y = 2\nx = p[0, 0, 0, 0, 0, 0] < y",
    "y = 0\nx = 5 % y",
    "x = [1, 2, 3]\ny = x[1.5e10]",
    'x = [1, 2, 3]\ny = x["a"]',
    "x = 3\ny = x[0]",
    "x = 3\nx.f = 2",
    "x = 3\ny = x.f",
    "movel(5)",
    "movej([1, 2])",
    'movel(p[0, 0, 0, 0, 0, 0], a="fast")',
    "set_standard_digital_out(9, True)",
    "set_standard_digital_out(1, 3)",
    "textmsg()",
    'sleep("x")',
    "x = sqrt(-1)",
    "x = pose_trans(1, 2)",
    "x = pose_inv([1, 2, 3])",
    'x = to_num("abc")',
    'x = norm("abc")',
    "x = struct(1, 2)",
    "x = rpy2rotvec(5)",
    "kill 3",
    'join "x"',
    "x = read_input_integer_register(99)",
    'write_output_integer_register(24, "a")',
    "set_tcp(5)",
    "x = length(5)",
    "x = 1e30 * 1e30\ny = [1][x]",
    "x = get_actual_tcp_pose()",
    'x = True + "a"',
    "x = [p[0, 0, 0, 0, 0, 0]]\nx[0].q = 1",
    "x = undefined_thing + 1",
    "x = [1, 2]\ny = x + 1",
    "def f(a):\n  return a\nend\nx = f(1, 2)",
]


@pytest.mark.filterwarnings("ignore:overflow:RuntimeWarning")
@pytest.mark.parametrize("body", BAD_UR)
def test_no_python_names_in_urscript_messages(tmp_path, body):
    path = tmp_path / "bad.script"
    path.write_text("def bad():\n" + "".join(f"  {line}\n" for line in body.splitlines()) + "end\n")
    for args in (["run", path], ["run", path, "--json"], ["check", path]):
        result = invoke(*args)
        assert result.exception is None or isinstance(result.exception, SystemExit), result.output
        assert not PYTHON_WORDS.search(result.output), result.output


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("t.src", 'DEF T()\nDECL INT X\nDECL REAL R\nR = 1.5\nX = R + "a"\nEND\n'),
        ("t.src", "DEF T()\nDECL INT X\nX = 0\nX = 5 / X\nEND\n"),
        ("t.src", "DEF T()\nDECL FRAME F\nDECL REAL R\nR = F.Q\nEND\n"),
        ("t.mod", 'MODULE T\nPROC main()\n  VAR num x;\n  x := 1 + "a";\nENDPROC\nENDMODULE\n'),
        ("t.mod", "MODULE T\nPROC main()\n  VAR pose p;\n  VAR num x;\n  x := p.q;\nENDPROC\nENDMODULE\n"),
    ],
)
def test_no_python_names_in_the_cores_messages_of_other_languages(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    result = invoke("run", path)
    assert result.exit_code != 0 and not PYTHON_WORDS.search(result.output), result.output


def test_inputs_nothing_provides_are_named_as_simulated_io(tmp_path):
    path = tmp_path / "sim.script"
    path.write_text("def p():\n  x = get_tool_digital_in(0)\n  y = get_standard_digital_in(3)\nend\n")
    result = invoke("run", path)
    assert "simulated I/O (no device or declaration provides it): tool_digital_in[0], standard_digital_in[3]" in (
        result.output
    )
    given = json.loads(invoke("run", path, "--signal", "standard_digital_in[3]=1", "--json").output)
    assert given["simulated_io"] == ["tool_digital_in[0]"]
