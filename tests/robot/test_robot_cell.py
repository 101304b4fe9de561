"""The arm in the cell: catalogue against independent models, [cell.robot]/[cell.tool]/config errors, the
envelope check at generate time, and the configurations the programs carry against an independent model."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from click.testing import CliRunner
from support.robot_chains import CATALOGUE_CHAINS, chain_frames, ikpy_chain

from codegen.cli import main
from codegen.kinds.station.region import arm_poses
from codegen.kinds.station.section import stations_of
from codegen.model.cell import DEMO_CELL, EXAMPLES_DIR, CellError, load_cell
from codegen.render import render
from codegen.robot.arms import catalogue

DEMO_TEXT = DEMO_CELL.read_text()
BENCH = EXAMPLES_DIR / "thermometer_bench.toml"


def write_cell(tmp_path, text: str, name: str = "cell.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def generate(tmp_path, cell_path, *args):
    return CliRunner().invoke(main, ["generate", str(cell_path), "--out", str(tmp_path / "out"), *args])


# --- catalogue ------------------------------------------------------------------------------------


@pytest.mark.parametrize("model", sorted(CATALOGUE_CHAINS))
def test_catalogue_forward_kinematics_agrees_with_the_vendor_model(model):
    """Each catalogue arm's closed form against an ikpy chain built from the joint origins of its
    published model (not from the catalogue's parameters)."""
    arm = catalogue()[model]
    chain, active = ikpy_chain(CATALOGUE_CHAINS[model])
    rng = np.random.default_rng(3)
    limits = arm.limits
    for q in rng.uniform(limits[:, 0], limits[:, 1], (25, 6)):
        angles = np.zeros(len(active))
        angles[active] = np.radians(q)
        expected = chain.forward_kinematics(angles)
        got = arm.kin.fk(q)
        assert np.abs(got[:3, 3] - expected[:3, 3]).max() < 1e-6, model
        assert np.abs(got[:3, :3] - expected[:3, :3]).max() < 1e-9, model


def test_catalogue_lists_the_arms_the_issue_names_with_sources():
    names = set(catalogue())
    for model in (
        "UR3e",
        "UR5e",
        "UR10e",
        "UR16e",
        "IRB 140",
        "IRB 1200-5/0.9",
        "IRB 1600-10/1.45",
        "IRB 4600-60/2.05",
        "KR 6 R900 sixx",
        "KR 10 R1100 sixx",
    ):
        assert model in names
    assert any(name.startswith("KR 210 R2700") for name in names)
    for arm in catalogue().values():
        assert arm.source and arm.reach_mm and arm.payload_kg
        home = np.array(arm.home_deg)
        assert np.all(home > arm.limits[:, 0]) and np.all(home < arm.limits[:, 1])


def test_every_home_position_is_reached_back_through_inverse_kinematics():
    for arm in catalogue().values():
        solutions = arm.kin.ik(arm.kin.fk(np.array(arm.home_deg)))
        assert np.nanmin(np.abs(solutions - arm.home_deg).max(axis=-1)) < 1e-6, arm.model


# --- cell file errors -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('kuka = "KR 10 R1100 sixx"', 'kuka = "KR 99"', "cell.robot.kuka: unknown arm 'KR 99'"),
        ('kuka = "KR 10 R1100 sixx"', 'kuka = "UR10e"', "UR10e is a ur arm; the kuka controller drives kuka arms"),
        ('abb = "IRB 1600-10/1.45"\n', 'abb = "IRB 1600-10/1.45"\ndtrans = "UR5e"\n', "cell.robot.dtrans"),
        ("mass_kg = 1.5", "mass_kg = 0.0", "cell.tool.mass_kg"),
        ("cog_mm = [0.0, 0.0, 80.0]", "cog_mm = [0.0, 0.0]", "cell.tool.cog_mm"),
        (
            "home = { ur = [180.0, -90.0, 90.0, -90.0, -90.0, 0.0], kuka = [0.0, -90.0, 90.0, 0.0, 90.0, 30.0], "
            "abb = [0.0, 0.0, 0.0, 0.0, 90.0, 30.0] }",
            "home = { kuka = [0, -90, 90, 0, 170, 0] }",
            "cell.robot.home.kuka[4]: axis 5 at 170 deg is outside its limits",
        ),
        (
            'abb = "IRB 1600-10/1.45"\n',
            'abb = "IRB 1600-10/1.45"\njoint_margin_deg = -1\n',
            "cell.robot.joint_margin_deg",
        ),
    ],
)
def test_robot_section_errors_name_the_key(tmp_path, old, new, message):
    assert old in DEMO_TEXT
    path = write_cell(tmp_path, DEMO_TEXT.replace(old, new, 1))
    with pytest.raises(CellError, match=re.escape(message)):
        load_cell(path)
    result = generate(tmp_path, path)
    assert result.exit_code == 2 and message in result.output and "Traceback" not in result.output
    assert not (tmp_path / "out").exists()


def test_an_unknown_arm_is_answered_with_the_arms_of_its_controller_and_the_custom_table(tmp_path):
    path = write_cell(tmp_path, DEMO_TEXT.replace('kuka = "KR 10 R1100 sixx"', 'kuka = "KR 20 R1810"', 1))
    with pytest.raises(CellError) as caught:
        load_cell(path)
    message = str(caught.value)
    assert "cell.robot.kuka: unknown arm 'KR 20 R1810'" in message
    assert "KR 6 R900 sixx" in message and "KR 210 R2700 extra" in message
    assert "UR10e" not in message and "IRB" not in message  # arms the kuka controller cannot drive
    assert "{ model, family, params, limits_deg, home_deg }" in message


def test_a_custom_arm_by_its_parameters(tmp_path):
    custom = (
        'kuka = { model = "my KR", family = "opw", params = { a1 = 25, a2 = -35, b = 0, c1 = 400, c2 = 560, '
        "c3 = 515, c4 = 80, offsets_deg = [0, 90, 0, 0, 0, 0], signs = [-1, 1, 1, -1, 1, -1] }, "
        "limits_deg = [[-170, 170], [-190, 45], [-120, 156], [-185, 185], [-120, 120], [-350, 350]], "
        "home_deg = [0, -90, 90, 0, 90, 0] }"
    )
    cell = load_cell(write_cell(tmp_path, DEMO_TEXT.replace('kuka = "KR 10 R1100 sixx"', custom)))
    same = load_cell(DEMO_CELL)
    station = stations_of(cell)[0]
    mine = [p.joints for p in arm_poses(cell, "kuka", station)]
    theirs = [p.joints for p in arm_poses(same, "kuka", stations_of(same)[0])]
    assert np.allclose(mine, theirs)


def test_station_config_is_validated(tmp_path):
    text = DEMO_TEXT.replace(
        "chuck = [738.5, -112.3, 305.2, 90.0, 0.0, 180.0]\n",
        "chuck = [738.5, -112.3, 305.2, 90.0, 0.0, 180.0]\n[station.config.abb]\nchuk = [0, 0, 0, 0]\n",
        1,
    )
    with pytest.raises(CellError, match=r"station\[0\]\.config\.abb\.chuk: no such pose"):
        load_cell(write_cell(tmp_path, text))


def test_a_configuration_the_pose_cannot_take_is_refused_at_generate(tmp_path):
    text = DEMO_TEXT.replace(
        "chuck = [738.5, -112.3, 305.2, 90.0, 0.0, 180.0]\n",
        "chuck = [738.5, -112.3, 305.2, 90.0, 0.0, 180.0]\n[station.config.abb]\napproach = [1, 0, 0, 0]\n",
        1,
    )
    result = generate(tmp_path, write_cell(tmp_path, text))
    assert result.exit_code == 2, result.output
    assert "station 1 'lathe_1' pose 'approach' (abb, IRB 1600-10/1.45)" in result.output
    assert "configuration (1, 0, 0, 0)" in result.output


def test_taught_joints_name_the_solution(tmp_path):
    cell = load_cell(DEMO_CELL)
    joints = arm_poses(cell, "ur", stations_of(cell)[0])[0].joints
    flipped = joints.copy()
    flipped[4] = -flipped[4]  # another wrist: does not reach the pose
    text = DEMO_TEXT.replace(
        "chuck = [738.5, -112.3, 305.2, 90.0, 0.0, 180.0]\n",
        "chuck = [738.5, -112.3, 305.2, 90.0, 0.0, 180.0]\n[station.config.ur]\n"
        f"approach = {{ joints = [{', '.join(f'{v:.4f}' for v in flipped)}] }}\n",
        1,
    )
    result = generate(tmp_path, write_cell(tmp_path, text))
    assert result.exit_code == 2 and "do not reach this pose" in result.output


# --- the envelope check ---------------------------------------------------------------------------


def test_demo_cells_pass_with_their_margins_printed(tmp_path):
    result = generate(tmp_path, DEMO_CELL)
    assert result.exit_code == 0, result.output
    assert "envelope abb (IRB 1600-10/1.45): 298 readings per station, every pose reachable" in result.output
    assert re.search(r"station 6 inspection_table: [\d.]+ deg to the nearest joint limit", result.output)
    data = json.loads(generate(tmp_path, BENCH, "--json").output)
    kuka = next(e for e in data["envelope"] if e["target"] == "kuka")
    assert kuka["arm"] == "KR 6 R900 sixx" and kuka["stations"][0]["wrist_margin_deg"] > 5


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        # the gate's shelf moved 255 mm further out: taught within reach, but not every correction of its
        # retreat (50 mm above it, [cell.motion] retreat_mm), which reaches further than the shelf
        (
            "shelf = [-60.5, -905.2, 388.0",
            "shelf = [-60.5, -1160.0, 388.0",
            "station 7 'warehouse_gate' pose 'retreat' (ur, UR10e): out of reach or beyond a joint limit",
        ),
        # the gauge lowered towards the wrist singularity of the ABB arm (axis 5 near 0)
        (
            "gauge = [452.3, 561.8, 142.5",
            "gauge = [452.3, 561.8, 110.0",
            "station 6 'inspection_table' pose 'gauge' (abb, IRB 1600-10/1.45): the wrist comes within 3.11 deg",
        ),
        # lowered further: the corrections cross the singularity, the wrist would flip
        (
            "gauge = [452.3, 561.8, 142.5",
            "gauge = [452.3, 561.8, 62.5",
            "station 6 'inspection_table' pose 'gauge' (abb, IRB 1600-10/1.45): the arm would change configuration",
        ),
    ],
)
def test_a_station_outside_the_envelope_is_refused(tmp_path, old, new, message):
    assert old in DEMO_TEXT
    result = generate(tmp_path, write_cell(tmp_path, DEMO_TEXT.replace(old, new)))
    assert result.exit_code == 2, result.output
    assert message in result.output and "for the reading (shift" in result.output
    assert "Traceback" not in result.output and not (tmp_path / "out").exists()


def test_the_margins_name_the_pose_nearest_the_wrist_singularity(tmp_path):
    """The gauge lowered towards the ABB arm's wrist singularity (3.11 deg from it, as the refusal above says) with a
    margin of 1 deg asked (and its table lowered as much): accepted, and the station's margins name the gauge as the
    pose nearest the singularity (its least joint margin is at another pose)."""
    text = DEMO_TEXT
    for old, new in (
        ("gauge = [452.3, 561.8, 142.5", "gauge = [452.3, 561.8, 110.0"),
        ("pose = [475.0, 610.0, -148.8", "pose = [475.0, 610.0, -181.3"),
        ('abb = "IRB 1600-10/1.45"\n', 'abb = "IRB 1600-10/1.45"\nwrist_margin_deg = 1\n'),
    ):
        assert old in text
        text = text.replace(old, new)
    result = generate(tmp_path, write_cell(tmp_path, text), "--target", "abb", "--json")
    assert result.exit_code == 0, result.output
    abb = next(e for e in json.loads(result.output)["envelope"] if e["target"] == "abb")
    station = next(s for s in abb["stations"] if s["name"] == "inspection_table")
    assert station["wrist_pose"] == "gauge" and station["pose"] != "gauge"
    assert station["wrist_margin_deg"] == pytest.approx(3.11, abs=0.005)
    text_result = generate(tmp_path, write_cell(tmp_path, text), "--target", "abb")
    assert "from its singularity (pose gauge)" in text_result.output


def test_a_taught_pose_out_of_reach_is_refused(tmp_path):
    text = DEMO_TEXT.replace("shelf = [-60.5, -905.2, 388.0", "shelf = [-60.5, -1405.2, 388.0")
    result = generate(tmp_path, write_cell(tmp_path, text))
    assert result.exit_code == 2
    assert "station 7 'warehouse_gate' pose 'shelf' (ur, UR10e): out of reach: the flange would be at" in result.output
    assert "beyond the UR10e's reach of 1,300 mm" in result.output  # the data sheet's (docs/arm.md)
    # the tool's 200 mm along z of a pose pointing down (c = 180): the flange 200 mm above the TCP
    assert "(-60, -1405, 588) mm, 1,524 mm from the base" in result.output  # hypot(60.5, 1405.2, 588) = 1524.5


def test_a_tight_joint_margin_is_refused(tmp_path):
    text = DEMO_TEXT.replace('abb = "IRB 1600-10/1.45"\n', 'abb = "IRB 1600-10/1.45"\njoint_margin_deg = 25\n')
    result = generate(tmp_path, write_cell(tmp_path, text))
    assert result.exit_code == 2 and "of its limit (margin asked: 25 deg)" in result.output


# --- the configurations in the programs against an independent model ------------------------------


def _side(frames, q):
    """cfx / Status bits from the ikpy model's link frames: the wrist centre (axis 5's origin) in front
    of axis 1, in front of the lower arm (axis 2 -> axis 3), and the sign of axis 5."""
    forward = frames[0][:3, 0] * np.array([1.0, 1.0, 0.0])  # axis 1's frame: x points to the front
    forward /= np.linalg.norm(forward)
    j2, j3, wrist = frames[1][:3, 3], frames[2][:3, 3], frames[4][:3, 3]
    front_of_axis1 = float(wrist @ forward) >= 0
    lower = j3 - j2
    normal = lower[2] * forward - (lower @ forward) * np.array([0.0, 0.0, 1.0])  # the lower arm turned forward
    front_of_lower_arm = float((wrist - j3) @ normal) >= 0
    return front_of_axis1, front_of_lower_arm, q[4] >= 0


def test_demo_robconf_and_status_turn_agree_with_an_independent_model():
    cell = load_cell(DEMO_CELL)
    files = {f.relpath.rsplit("/", 1)[1]: f.text for f in render(cell, ["abb", "kuka"])}
    checked = 0
    for target in ("abb", "kuka"):
        model = cell.robot.arms[target].model
        for station in stations_of(cell):
            for pose in arm_poses(cell, target, station):
                frames = chain_frames(model, pose.joints)
                flange = frames[-1] @ np.eye(4)
                want = pose.tcp2base @ np.linalg.inv(cell.robot.tool.tcp2flange)
                assert np.abs(flange - want).max() < 1e-6  # the joints reach the taught pose (independent FK)
                front1, front_lower, a5_positive = _side(frames, pose.joints)
                retreat = pose.name == "retreat"  # its data is named after the work pose
                ident = f"r{station.id}_{station.poses[-1].name}" if retreat else f"p{station.id}_{pose.name}"
                if target == "abb":
                    text = files["agv_machine_tending.mod"]
                    robconf = re.search(rf"CONST robtarget {ident} := \[.*?\], \[.*?\], \[(.*?)\]", text).group(1)
                    quadrants = [int(np.floor(pose.joints[i] / 90.0)) for i in (0, 3, 5)]
                    cfx = 4 * (not front1) + 2 * (not front_lower) + (not a5_positive)
                    assert robconf == ", ".join(str(v) for v in [*quadrants, cfx])
                else:
                    text = files["agv_machine_tending.dat"]
                    decl = re.search(rf"DECL E6POS {ident.upper()}=\{{(.*?)\}}", text).group(1)
                    status = int(re.search(r",S (\d+)", decl).group(1))
                    assert status == (not front1) + 2 * front_lower + 4 * (not a5_positive)
                    turn = re.search(r",T (\d+)", decl)
                    if turn:
                        assert int(turn.group(1)) == sum(1 << i for i in range(6) if pose.joints[i] < 0)
                checked += 1
    assert checked == 2 * sum(len(s.poses) + 1 for s in stations_of(cell))  # each station's taught poses, its retreat


def test_the_controllers_numbered_tool_instead_of_a_declared_one(tmp_path):
    text = DEMO_TEXT.replace("cog_mm = [0.0, 0.0, 80.0]", "cog_mm = [0.0, 0.0, 80.0]\nnumbered = { kuka = 3 }")
    cell = load_cell(write_cell(tmp_path, text))
    src, dat, *_ = (f.text for f in render(cell, ["kuka"]))  # and the vision channel's configuration
    assert "  $TOOL = TOOL_DATA[3]\n  $LOAD = LOAD_DATA[3]\n" in src and "DECL FRAME VIS_TOOL" not in dat
    from support import stations

    cases = [c for c in stations.build_cases(cell, 3, 1) if c.reading.station_id == 1]
    assert stations.verify(cell, stations.source(cell, "kuka"), cases).mismatches == 0
    other = stations.source(cell, "kuka", src.replace("TOOL_DATA[3]", "TOOL_DATA[4]"), dat, "other")  # a tool lacking
    report = stations.verify(cell, other, cases)
    assert report.mismatches == report.cases
    # TOOL_DATA[4] as a fresh controller has it (a zero frame, the run warns naming it): the flange, 200 mm off
    assert "position error 200.000000 mm" in report.first_mismatches[0]
    bad = DEMO_TEXT.replace("cog_mm = [0.0, 0.0, 80.0]", "cog_mm = [0.0, 0.0, 80.0]\nnumbered = { abb = 1 }")
    with pytest.raises(CellError, match=r"cell.tool.numbered.abb: the abb controller has no numbered tools here"):
        load_cell(write_cell(tmp_path, bad, "bad.toml"))


def _many_stations(count: int, bad: int | None = None) -> str:
    """The demo's arm section with count copies of its lathe station (station `bad` out of reach)."""
    head = DEMO_TEXT[: DEMO_TEXT.index("[[station]]")]
    stations = []
    for i in range(1, count + 1):
        x = 738.5 + (i % 5) - (0 if i != bad else -2000.0)
        stations.append(
            f'[[station]]\nid = {i}\nname = "lathe_{i}"\nmark = [612.4, -285.0, 1.8]\n[station.poses]\n'
            f"approach = [655.0, -120.0, 420.0, 90.0, 0.0, 180.0]\nchuck = [{x}, -112.3, 305.2, 90.0, 0.0, 180.0]\n"
        )
    return head + "\n".join(stations)


def test_a_large_cell_is_checked_in_parallel_with_the_same_result(tmp_path, monkeypatch):
    from codegen.kinds.station import plan

    # the parallel path from 16 stations on (not the product's 50): the same chunks and processes, a third of the work
    large = 16
    monkeypatch.setattr(plan, "PARALLEL_STATIONS", large)
    path = write_cell(tmp_path, _many_stations(large))
    parallel = load_cell(path)
    assert len(stations_of(parallel)) >= plan.PARALLEL_STATIONS
    margins = [e.as_json() for e in plan.check(parallel)]
    files = render(parallel)
    monkeypatch.setattr(plan, "PARALLEL_STATIONS", 10**6)
    serial = load_cell(path)
    assert [e.as_json() for e in plan.check(serial)] == margins
    assert [f.text for f in render(serial)] == [f.text for f in files]
    refused = load_cell(write_cell(tmp_path, _many_stations(large, bad=13), "bad.toml"))
    monkeypatch.setattr(plan, "PARALLEL_STATIONS", large)
    with pytest.raises(plan.ReachError, match=r"station 13 'lathe_13' pose 'chuck' \(ur, UR10e\): out of reach"):
        plan.check(refused)


def test_a_first_pose_half_a_turn_from_home_for_some_readings_is_refused_at_generate(tmp_path):
    """The demo with KUKA's catalogue home (axis 6 at 0): the grinder's approach (a vertical tool: no Turn named)
    has axis 6 about 180 deg from home for some readings, so the controller's shortest turn would go one way for
    some readings and the other way for others. generate refuses it, naming the pose and what to change; the
    demo's home (axis 6 at 30) is taken."""
    home = "kuka = [0.0, -90.0, 90.0, 0.0, 90.0, 30.0]"
    assert home in DEMO_TEXT
    text = DEMO_TEXT.replace(home, "kuka = [0.0, -90.0, 90.0, 0.0, 90.0, 0.0]", 1)
    result = generate(tmp_path, write_cell(tmp_path, text), "--target", "kuka")
    assert result.exit_code == 2, result.output
    assert "station 5 'grinder' pose 'approach' (kuka, KR 10 R1100 sixx)" in result.output
    assert "about half a turn away for some readings" in result.output and "[cell.robot.home]" in result.output
    assert generate(tmp_path, write_cell(tmp_path, DEMO_TEXT), "--target", "kuka").exit_code == 0


def test_the_arm_pages_custom_arm_example_is_the_catalogue_arm_it_says():
    import re
    import tomllib
    from pathlib import Path

    from codegen.robot.arms import arm_from_table, find_arm

    page = (Path(__file__).resolve().parents[2] / "docs" / "arm.md").read_text(encoding="utf-8")
    block = re.search(r"```toml\n(\[cell\.robot\]\nkuka = \{ model = \"my KR 10\".*?)```", page, re.S).group(1)
    table = tomllib.loads(block)["cell"]["robot"]["kuka"]
    mine, theirs = arm_from_table({"vendor": "kuka", **table}, "docs/arm.md"), find_arm("KR 10 R1100 sixx")
    rng = np.random.default_rng(1)
    for _ in range(20):
        q = rng.uniform(-90, 90, 6)
        assert np.allclose(mine.kin.fk(q), theirs.kin.fk(q), atol=1e-9)
    assert (mine.reach_mm, mine.payload_kg) == (theirs.reach_mm, theirs.payload_kg)
