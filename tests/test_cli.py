"""Command line: derive --check, correct against a hand-written 4x4 computation, import budget."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from codegen.cli import main


def run(*args):
    return CliRunner().invoke(main, list(args))


@pytest.mark.slow
def test_derive_check_exits_0():
    result = run("derive", "--check")
    assert result.exit_code == 0, result.output
    assert "all identities as expected" in result.output
    assert "zero_rotation_is_translation" in result.output


def test_derive_json():
    result = run("derive", "--check", "--json")
    data = json.loads(result.output)
    assert data["ok"] is True
    assert {i["name"] for i in data["identities"]} >= {"rigid", "source_eq13"}


def _hand_matrix(x, y, z, a, b, c):
    """Written out here, not imported: R = Rz(a) Ry(b) Rx(c), angles in degrees."""
    a, b, c = (math.radians(v) for v in (a, b, c))
    rz = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rx = np.array([[1, 0, 0], [0, math.cos(c), -math.sin(c)], [0, math.sin(c), math.cos(c)]])
    m = np.eye(4)
    m[:3, :3] = rz @ ry @ rx
    m[:3, 3] = (x, y, z)
    return m


def test_correct_matches_hand_computation():
    # Demo station 3 (mill_1): mark (640.2, 210.6, 2.4); reading (643.2, 206.6, 5.4); sign -1. Its tray poses are
    # fixed (the tray rides on the AGV with the robot): as taught; the machine's poses are corrected.
    result = run("correct", "--station", "3", "--mark", "643.2,206.6,5.4", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    phi = math.radians(-1 * (5.4 - 2.4))
    trans_tn = np.eye(4)
    trans_tn[:2, 3] = (643.2, 206.6)
    rot = np.eye(4)
    rot[:2, :2] = [[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]]
    trans_minus_t = np.eye(4)
    trans_minus_t[:2, 3] = (-640.2, -210.6)
    d = trans_tn @ rot @ trans_minus_t
    assert np.allclose(np.array(data["correction"]), d, atol=1e-9)
    above, at = (600.0, 40.0, 450.0, -90.0, 15.0, 180.0), (702.6, 55.8, 262.4, -90.0, 15.0, 180.0)
    tray = {name: (x, -480.0, z, -90.0, 0.0, 180.0) for name, x, z in _TRAY}
    taught = {"approach": above, "vise_out": at, "vise_clear": above, **tray, "vise_above": above, "vise": at}
    assert [p["name"] for p in data["poses"]] == list(taught)
    assert [p["motion"] for p in data["poses"]] == ["joint"] + ["linear"] * 10
    for pose in data["poses"]:
        fixed = pose["name"] in tray
        expected = (np.eye(4) if fixed else d) @ _hand_matrix(*taught[pose["name"]])
        kuka = pose["targets"]["kuka"]
        assert np.allclose(kuka[:3], expected[:3, 3], atol=1e-4)
        assert np.allclose(_hand_matrix(*kuka)[:3, :3], expected[:3, :3], atol=1e-6)
        assert math.isclose(kuka[3], -90.0 + (0.0 if fixed else math.degrees(phi)), abs_tol=1e-9)  # yaw addition
        ur = pose["targets"]["ur"]
        assert np.allclose(np.array(ur[:3]) * 1000, expected[:3, 3], atol=1e-3)
        w, qx, qy, qz = pose["targets"]["abb"][3:]
        assert math.isclose(w * w + qx * qx + qy * qy + qz * qz, 1.0, abs_tol=1e-6)


# the demo's tray poses (x, z; y -480): the finished part put down at x 520, the raw part taken at x 400
_TRAY = [
    ("tray_done_above", 520.0, 370.0),
    ("tray_done", 520.0, 250.0),
    ("tray_done_up", 520.0, 370.0),
    ("tray_raw_above", 400.0, 370.0),
    ("tray_raw", 400.0, 250.0),
    ("tray_raw_up", 400.0, 370.0),
]


def test_correct_halt_is_reported():
    result = run("correct", "--station", "1", "--mark", "700,-285,1.8")
    assert result.exit_code == 0
    assert "HALT (shift_over_limit): station lathe_1: mark shift over 10 mm, recalibrate" in result.output


def test_correct_bad_mark_is_exit_2():
    result = run("correct", "--station", "1", "--mark", "1,2")
    assert result.exit_code == 2
    assert "--mark: expected X,Y,THETA" in result.output


def test_correct_does_not_import_sympy_jinja_lark():
    code = (
        "import sys\n"
        "from codegen.cli import main\n"
        "try:\n"
        "    main(['correct', '--station', '1', '--mark', '613,-284,2'])\n"
        "except SystemExit:\n"
        "    pass\n"
        "bad = [m for m in ('sympy', 'jinja2', 'lark') if m in sys.modules]\n"
        "print('LOADED', bad)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert "LOADED []" in out


def test_run_refuses_a_data_file():
    from pathlib import Path

    kuka = Path(__file__).resolve().parents[1] / "generated" / "agv_machine_tending" / "kuka"
    refused = CliRunner().invoke(main, ["run", str(kuka / "agv_machine_tending.dat")])
    assert refused.exit_code == 2 and "a data file" in refused.output
    inputs = ["VIS_STATION=1", "VIS_X=612.4", "VIS_Y=-285", "VIS_THETA=1.8"]
    ran = CliRunner().invoke(main, ["run", str(kuka / "agv_machine_tending.src"), *(f"--input={i}" for i in inputs)])
    assert ran.exit_code == 0 and "738.5000 -112.3000 305.2000" in ran.output


def test_diff_without_a_cell_checks_every_bundled_cell(tmp_path):
    import shutil
    from pathlib import Path

    generated = Path(__file__).resolve().parents[1] / "generated"
    shutil.copytree(generated, tmp_path / "out")
    assert CliRunner().invoke(main, ["diff", "--out", str(tmp_path / "out")]).exit_code == 0
    edited = tmp_path / "out" / "thermometer_bench" / "abb" / "thermometer_bench.mod"
    edited.write_text(edited.read_text().replace("MoveL", "MoveJ", 1))
    result = CliRunner().invoke(main, ["diff", "--out", str(tmp_path / "out")])
    assert result.exit_code == 1 and "thermometer_bench.mod" in result.output


def test_negative_jobs_and_step_limit_are_refused():
    from pathlib import Path

    prog = str(Path(__file__).resolve().parents[1] / "generated/agv_machine_tending/ur/agv_machine_tending.script")
    assert CliRunner().invoke(main, ["verify", "--jobs", "-1"]).exit_code == 2
    assert CliRunner().invoke(main, ["run", prog, "--step-limit", "-1"]).exit_code == 2


def test_run_refuses_an_input_the_program_does_not_read():
    from pathlib import Path

    generated = Path(__file__).resolve().parents[1] / "generated" / "agv_machine_tending"
    at_home = ["--start", "180,-90,90,-90,-90,0"]  # the UR's home in the demo cell (its program checks it)
    for program, good, bad, start in (
        (generated / "kuka" / "agv_machine_tending.src", "VIS_STATION=3", "VIS_STATON=3", []),
        (generated / "ur" / "agv_machine_tending.script", "input_integer_register_24=3", "input_intger=3", at_home),
        (generated / "abb" / "agv_machine_tending.mod", "vis_station=3", "vis_statio=3", ["--start", "0,0,0,0,90,0"]),
        (generated / "dtrans" / "agv_machine_tending.prg", "markp[0]=1.0", "mark[0]=1.0", []),
    ):
        ran = CliRunner().invoke(main, ["run", str(program), "--input", good, *start])
        assert ran.exit_code == 0, ran.output
        result = CliRunner().invoke(main, ["run", str(program), "--input", bad])
        assert result.exit_code == 2 and "has no such variable or register" in result.output, result.output


@pytest.mark.parametrize(
    ("name", "content", "exit_code", "message"),
    [
        ("bad.script", b'def p():\n  textmsg("\xff\xfe")\nend\n', 2, "not UTF-8 text (byte 20)"),
        ("big.script", f"def p():\n  x = {'9' * 5000}\nend\n".encode(), 2, "more digits than a controller reads"),
        ("few.script", b"def p():\n  x = read_input_float_register()\nend\n", 1, "too few arguments (0 given)"),
        ("sin.src", b"DEF T()\nDECL REAL R\nR = SIN()\nEND\n", 1, "SIN: too few arguments"),
        ("fmt.prg", b'TPWrite 0, "%.999999f", 1.0\n', 1, "wider than a message (80 characters)"),
    ],
)
def test_hostile_program_files_get_a_message_not_a_traceback(tmp_path, name, content, exit_code, message):
    """Found by a fault probe: each of these raised a Python error."""
    path = tmp_path / name
    path.write_bytes(content)
    result = CliRunner().invoke(main, ["run", str(path)])
    assert result.exit_code == exit_code and message in result.output, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)


@pytest.mark.parametrize("bad", ["markp[5]=1", "markp[-1]=400", "markp[x]=1"])
def test_an_input_element_out_of_bounds_is_refused(bad):
    from pathlib import Path

    program = Path(__file__).resolve().parents[1] / "generated/agv_machine_tending/dtrans/agv_machine_tending.prg"
    result = CliRunner().invoke(main, ["run", str(program), "--input", "weizhi=1", "--input", bad])
    assert result.exit_code == 2 and "has no such variable or register" in result.output


@pytest.mark.parametrize(
    ("name", "content", "message"),
    [
        ("grow.src", b"DEF T()\nDECL INT X\nX = 2\nLOOP\nX = X * X\nENDLOOP\nEND\n", "out of the INT range"),
        (
            "digits.mod",
            b"MODULE T\nPROC main()\n  TPWrite NumToStr(1, 100000000);\nENDPROC\nENDMODULE\n",
            "NumToStr decimals",
        ),
        (
            "double.script",
            b'def p():\n  s = "ab"\n  while True:\n    s = str_cat(s, s)\n  end\nend\n',
            "longer than 1023",
        ),
    ],
)
def test_values_have_the_controllers_limits(tmp_path, name, content, message):
    """Found by a fault probe: these grew without bound (gigabytes, or hung) instead of failing as on
    the controller: KRL INT is 32-bit, RAPID strings hold 80 characters, UR string results 1,023."""
    path = tmp_path / name
    path.write_bytes(content)
    result = CliRunner().invoke(main, ["run", str(path)])
    assert result.exit_code == 1 and message in result.output, result.output


def test_a_huge_expression_is_refused_before_parsing(tmp_path):
    """A 400 kB expression took seconds and hundreds of megabytes to refuse as nested too deeply."""
    path = tmp_path / "huge.script"
    path.write_text("def p():\n  x = " + "+".join(["1"] * 200_000) + "\nend\n")
    result = CliRunner().invoke(main, ["run", str(path)])
    assert result.exit_code == 2 and "huge.script: line 2: longer than 10,000 characters" in result.output


REPO_ROOT = Path(__file__).resolve().parents[1]
EXAMPLES_DIR = REPO_ROOT / "codegen" / "examples"
BELT = EXAMPLES_DIR / "conveyor_touches.csv"
TOUCHES = EXAMPLES_DIR / "agv_gripper_touches.csv"


UR_DEMO = Path(__file__).resolve().parents[1] / "generated/agv_machine_tending/ur/agv_machine_tending.script"
BAD_OPTIONS = [
    (
        [
            "calibrate",
            "conveyor",
            BELT,
            "--counter-bits",
            "16",
            "--working-length",
            "1500",
            "--max-residual",
            "nan",
        ],
        "--max-residual",
    ),
    (
        [
            "calibrate",
            "conveyor",
            BELT,
            "--counter-bits",
            "16",
            "--working-length",
            "1500",
            "--max-residual",
            "1_0",
        ],
        "--max-residual",
    ),
    (["calibrate", "conveyor", BELT, "--counter-bits", "16", "--working-length", "nan"], "--working-length"),
    (["calibrate", "conveyor", BELT, "--counter-bits", "16", "--working-length", "inf"], "--working-length"),
    (["calibrate", "conveyor", BELT, "--counter-bits", "16", "--working-length", "1e9"], "--working-length"),
    (
        [
            "calibrate",
            "conveyor",
            BELT,
            "--counter-bits",
            "16",
            "--working-length",
            "1500",
            "--camera-counts",
            "1e30,5",
        ],
        "--camera-counts",
    ),
    (
        ["calibrate", "conveyor", BELT, "--working-length", "1500", "--camera-counts", f"{10**30},5"],
        "--camera-counts",
    ),
    (
        [
            "calibrate",
            "conveyor",
            BELT,
            "--counter-bits",
            "16",
            "--working-length",
            "1500",
            "--camera-counts",
            "1,2,3",
        ],
        "--camera-counts",
    ),
    (["calibrate", "tcp", TOUCHES, "--max-uncertainty", "-1"], "--max-uncertainty"),
    (["calibrate", "tcp", TOUCHES, "--max-uncertainty", "nan"], "--max-uncertainty"),
    (["calibrate", "tcp", TOUCHES, "--max-uncertainty", "0"], "--max-uncertainty"),
    (["verify", "--cases", "-1"], "--cases"),
    (["verify", "--cases", "1_000"], "--cases"),
    (["verify", "--seed", "-1"], "--seed"),  # a laser cell's cases came from numpy, which takes no negative seed
    (["verify", "--jobs", "100000"], "--jobs"),
    (["verify", "--step-limit", "0"], "--step-limit"),
    (["correct", "--station", "1_0", "--mark", "1,2,3"], "--station"),
    (["generate", "--out", ""], "--out"),
    (["diff", "--out", ""], "--out"),
    (["pallet", "--svg", ""], "--svg"),
    (["run", str(UR_DEMO), "--max-seconds", "nan"], "--max-seconds"),
    (["run", str(UR_DEMO), "--max-seconds", "inf"], "--max-seconds"),
    (["run", str(UR_DEMO), "--max-moves", "1_0"], "--max-moves"),
]


@pytest.mark.parametrize(
    ("args", "option"), BAD_OPTIONS, ids=[f"{a[0]} {o}={a[a.index(o) + 1]}" for a, o in BAD_OPTIONS]
)
def test_options_take_finite_numbers_within_their_range(args, option, tmp_path, monkeypatch):
    """One parameter type (cli_base.Number, cli_base.Folder) for every numeric or folder option: exit 2, one
    message naming the option; nan, inf, 1_000 and values out of range never reach the command."""
    monkeypatch.chdir(tmp_path)  # an empty --out or --svg was the current folder
    result = run(*map(str, args))
    assert result.exit_code == 2, result.output
    errors = [line for line in result.output.splitlines() if line.startswith("Error")]
    assert len(errors) == 1 and f"'{option}'" in errors[0], result.output


def test_generate_into_an_empty_path_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = run("generate", str(EXAMPLES_DIR / "agv_machine_tending.toml"), "--out", "")
    assert result.exit_code == 2 and list(tmp_path.iterdir()) == [], result.output


def test_camera_counts_and_a_residual_bound_reach_the_fit():
    got = json.loads(
        run("calibrate", "conveyor", str(BELT), "--working-length", "1500", "--counter-bits", "16",
            "--camera-counts", "3625,59413", "--max-residual", "0.3", "--json").output
    )  # fmt: skip
    assert got["camera_offset_mm"] == pytest.approx(1200.1, abs=0.05)


@pytest.mark.parametrize(
    "cell",
    ["agv_machine_tending.toml", "conveyor/belt_pick.toml", "laser/laser_tcp.toml", "pallets/testmat_pallet.toml"],
)
def test_the_step_limit_reaches_every_kinds_runs(cell):
    """verify --step-limit 1: every run of every kind stops at its first step (the conveyor's and the laser's
    own limits applied in its place, and the runaways went unnoticed)."""
    from codegen.model.cell import load_cell

    path = EXAMPLES_DIR / cell
    target = load_cell(path).targets[0]
    result = run("verify", str(path), "--target", target, "--cases", "1", "--jobs", "1", "--step-limit", "1")
    mismatches = [line for line in result.output.splitlines() if line.strip().startswith("MISMATCH ")]
    assert result.exit_code == 1 and mismatches, result.output
    assert all("step limit 1 reached" in line for line in mismatches), result.output


def test_every_command_shows_its_help():
    """The option types print their metavar (a help page is the first place a bad type breaks)."""
    import click

    def walk(group, path):
        for name, command in group.commands.items():
            yield [*path, name]
            if isinstance(command, click.Group):
                yield from walk(command, [*path, name])

    for path in walk(main, []):
        result = run(*path, "--help")
        assert result.exit_code == 0, (path, result.output)


def test_run_starts_a_rapid_module_without_main_at_its_entry_routine(tmp_path):
    """A module loaded into the production task has no main: run names --entry, which starts it there (PP to
    Routine); a routine that does not exist, or --entry for a language without it, is one clear error (exit 2)."""
    module = tmp_path / "cal.mod"
    module.write_text(
        'MODULE cal\n  PROC cal_run()\n    TPWrite "cal ran";\n  ENDPROC\n'
        '  LOCAL PROC helper()\n    TPWrite "no";\n  ENDPROC\nENDMODULE\n'
    )
    without = run("run", str(module))
    assert without.exit_code == 2 and "--entry NAME" in without.output, without.output
    ran = run("run", str(module), "--entry", "cal_run")
    assert ran.exit_code == 0 and "cal ran" in ran.output, ran.output
    local = run("run", str(module), "--entry", "helper")
    assert local.exit_code == 2 and "no global PROC helper" in local.output, local.output
    script = tmp_path / "p.script"
    script.write_text('def p():\n  textmsg("x")\nend\n')
    other = run("run", str(script), "--entry", "p")
    assert other.exit_code == 2 and "starts only at its own entry" in other.output, other.output
