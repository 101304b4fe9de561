"""generate refuses a cell whose planned moves come within the clearance of a solid, naming the move, the body (link,
tool or part) and the solid; each variant is built here from geometry computed apart from the proof (the arm's
forward kinematics along the move), and the bundled cells' own solids stand where their programs clear them."""

from __future__ import annotations

import re
from types import SimpleNamespace

import numpy as np
import pytest
from click.testing import CliRunner
from support.cells import EXAMPLES, unstacking_testmat_text

from codegen.cli import main
from codegen.generate import GenerateError, check_clearance
from codegen.model.cell import CellError, load_cell
from codegen.poses import xyzabc_from_matrix
from codegen.render import joints_literal, render

UR_HOME = np.array([180.0, -90.0, 90.0, -90.0, -90.0, 0.0])


def with_world(tmp_path, name: str, text: str, before: str, extra: str, targets: str | None = None):
    """A bundled cell with `extra` lines put before the first line that starts with `before` (and its targets)."""
    source = EXAMPLES[name].read_text(encoding="utf-8")
    line = next(li for li in source.splitlines() if li.startswith(before))
    source = source.replace(line, extra + "\n" + line, 1)
    if targets is not None:
        source = re.sub(r"^targets = .*$", f"targets = {targets}", source, count=1, flags=re.M)
    path = tmp_path / f"{name}.toml"
    path.write_text(source + text, encoding="utf-8")
    return load_cell(path)


def _pose(matrix) -> str:
    return "[" + ", ".join(f"{float(v):.4f}" for v in xyzabc_from_matrix(matrix)) + "]"


def test_a_machine_moved_into_the_path_between_home_and_a_station_is_refused(tmp_path):
    """The UR's first move of station 1 (a joint move from home to its approach): the tool's tip halfway along it
    (forward kinematics of the mean joints: a joint move interpolates every axis); a 100 mm cube there."""
    demo = load_cell(EXAMPLES["agv_machine_tending"])
    arm, tcp2flange = demo.robot.arms["ur"], demo.robot.tool.tcp2flange
    approach = demo.kinds["station"].scene.paths(demo, ["ur"])[0].moves[0]
    middle = arm.kin.fk(0.5 * (UR_HOME + approach.joints)) @ tcp2flange
    extra = f"solids.lathe_3 = {{ box = [100.0, 100.0, 100.0], pose = {_pose(middle)} }}"
    cell = with_world(tmp_path, "agv_machine_tending", "", "solids.cabinet", extra)
    with pytest.raises(GenerateError) as caught:
        check_clearance(cell, ["ur"])
    said = str(caught.value)
    assert said.startswith("station 1 'lathe_1' pose 'approach' (nominal reading) (ur, UR10e): the ")
    assert "'lathe_3'" in said and "mm into it" in said and "cell.world.clearance_mm" in said
    assert re.search(r"the (tool|wrist_\d|forearm) touches", said)


def _testmat_cycle(target: str):
    cell = load_cell(EXAMPLES["testmat_pallet"])
    return cell, cell.kinds["pallet"].scene.paths(cell, [target])


def test_a_carried_box_that_sweeps_a_neighbouring_stack_is_refused(tmp_path):
    """The KUKA's first transit with a box (the joint move from Q over to the pallet): a stack of boxes declared
    where the carried box's centre is halfway along it (a 20 mm cube there, 5 mm lower: inside the 26 mm box but for
    2 mm at its bottom, 8 mm under the tool's tip). The part is refused against it, not the tool."""
    cell, paths = _testmat_cycle("kuka")
    arm, tcp2flange = cell.robot.arms["kuka"], cell.robot.tool.tcp2flange
    moves = paths[0].moves
    k = next(i for i, m in enumerate(moves) if m.kind == "joint" and m.carrying)
    middle = arm.kin.fk(0.5 * (np.asarray(moves[k - 1].joints) + np.asarray(moves[k].joints))) @ tcp2flange
    centre = middle @ np.array([0.0, 0.0, 13.0 + 5.0, 1.0])  # the box hangs along the tool's z from the TCP
    stack = np.eye(4)
    stack[:3, 3] = centre[:3]
    extra = f"[cell.world]\nsolids.stack_b = {{ box = [20.0, 20.0, 20.0], pose = {_pose(stack)} }}\n"
    cell = with_world(tmp_path, "testmat_pallet", "", "[cell.io]", extra)
    with pytest.raises(GenerateError) as caught:
        check_clearance(cell, ["kuka"])
    said = str(caught.value)
    assert said.startswith(f"{moves[k].where} (kuka, KR 6 R900 sixx): the part touches the solid 'stack_b'")


UR5E_FRONT = """[cell]
name = "ur5e_front"
targets = ["ur"]

[cell.camera]
angle_sign = 1

[cell.limits]
max_shift_mm = 5.0
max_rotation_deg = 5.0

[cell.robot]
ur = "UR5e"
{home}
[cell.tool]
tcp = [0.0, 0.0, 150.0, 0.0, 0.0, 0.0]
mass_kg = 1.0
cog_mm = [0.0, 0.0, 60.0]

[[station]]
id = 1
name = "press"
mark = [500.0, 0.0, 0.0]
[station.poses]
approach = [450.0, 0.0, 350.0, 0.0, 0.0, 180.0]
work = [500.0, 0.0, 180.0, 0.0, 0.0, 180.0]
[station.solids]
bed = {{ box = [300.0, 300.0, 150.0], pose = [550.0, 0.0, 75.0, 0.0, 0.0, 0.0] }}
"""


def _elbow_z(arm, joints) -> float:
    """The elbow's height (mm): the origin of the UR's link frame 2, from the forward kinematics."""
    return float(arm.kin.link_frames(np.asarray(joints, dtype=float)[None])[0][2, 2, 3])


def _nearest(solutions: np.ndarray, home) -> np.ndarray:
    """The solution nearest the home in joints (Euclidean, each axis turned by whole turns towards it: the UR's
    limits are +-360 deg): the controller's rule for get_inverse_kin(x, qnear=home)."""
    home = np.asarray(home, dtype=float)
    turned = solutions + 360.0 * np.round((home - solutions) / 360.0)
    return turned[np.nanargmin(np.linalg.norm(turned - home, axis=1))]


def test_a_ur5e_facing_away_from_its_station_is_generated_elbow_up(tmp_path):
    """A UR5e with its station in front (+x, the work 180 mm high over a press's bed whose top is 150 mm high) and the
    catalogue's home, which faces -x: the solution nearest the home reaches back over the shoulder, the elbow below
    the work's height, and the upper arm comes within the clearance of the bed. generate keeps the home and works the
    station elbow up (the branch that clears, nearest the home); the UR program steers get_inverse_kin to it."""
    path = tmp_path / "ur5e_front.toml"
    path.write_text(UR5E_FRONT.format(home=""), encoding="utf-8")
    cell = load_cell(path)
    arm = cell.robot.arms["ur"]
    assert list(cell.robot.home["ur"]) == [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]
    press = next(iter(cell.sections["station"].stations))
    flange = np.linalg.inv(cell.robot.tool.tcp2flange)
    work_flange = press.poses[1].matrix() @ flange
    nearest_home = _nearest(arm.kin.ik(work_flange), cell.robot.home["ur"])
    assert _elbow_z(arm, nearest_home) < 180.0  # the posture the home alone would give: elbow under the work
    assert check_clearance(cell, ["ur"])  # generated
    moves = cell.kinds["station"].scene.paths(cell, ["ur"])[0].moves
    assert _elbow_z(arm, moves[1].joints) > 180.0 + 200.0  # elbow up, well above the work
    np.testing.assert_allclose(arm.kin.fk(moves[1].joints), work_flange, atol=1e-6)  # the taught pose itself
    approach = moves[0].joints
    script = next(f.text for f in render(cell, ["ur"]) if f.relpath.endswith(".script"))
    qnear = ", ".join(str(v) for v in joints_literal(approach, "rad"))
    assert _elbow_z(arm, approach) > 180.0 and f"qnear=[{qnear}])" in script


def test_a_ur5e_posture_the_cell_names_is_kept_and_refused_naming_the_home_and_the_fix(tmp_path):
    """The cell's own configuration is authoritative: naming the elbow-down joints for the work ([station.config]) the
    cell is refused, naming the bed, the upper arm, the home in use and the home turned half a turn about axis 1."""
    path = tmp_path / "ur5e_front.toml"
    path.write_text(UR5E_FRONT.format(home=""), encoding="utf-8")
    free = load_cell(path)
    arm = free.robot.arms["ur"]
    press = next(iter(free.sections["station"].stations))
    flange = np.linalg.inv(free.robot.tool.tcp2flange)
    named = []
    for pose in press.poses:
        named.append(_nearest(arm.kin.ik(pose.matrix() @ flange), free.robot.home["ur"]))
    config = "[station.config.ur]\n" + "".join(
        f"{pose.name} = [{', '.join(f'{v:.6f}' for v in q)}]\n" for pose, q in zip(press.poses, named, strict=True)
    )
    path.write_text(UR5E_FRONT.format(home="") + config, encoding="utf-8")
    cell = load_cell(path)
    with pytest.raises(GenerateError) as caught:
        check_clearance(cell, ["ur"])
    said = str(caught.value)
    assert "'press: bed'" in said and "the upper_arm" in said and "[station.config.ur]" in said


BOXED_IN = """[cell.world]
solids.fence_a = { box = [2000.0, 100.0, 2000.0], pose = [0.0, 450.0, 1000.0, 0.0, 0.0, 0.0] }
solids.fence_b = { box = [2000.0, 100.0, 2000.0], pose = [0.0, -450.0, 1000.0, 0.0, 0.0, 0.0] }
solids.roof = { box = [2000.0, 2000.0, 100.0], pose = [0.0, 0.0, 900.0, 0.0, 0.0, 0.0] }

"""


def test_a_ur5e_boxed_in_so_that_no_posture_from_its_home_clears_is_refused_naming_the_home_and_the_fix(tmp_path):
    """The UR5e facing away from its station between two fences (y = +-400 mm) under a roof (850 mm high): from the
    catalogue's home every posture either keeps the elbow low over the bed or swings the arm half a turn, past a fence
    or under the roof. generate refuses, naming the home in use and the home turned half a turn about axis 1, from
    which the station is a short turn away; with that home the cell generates, elbow up."""
    path = tmp_path / "ur5e_front.toml"
    path.write_text(UR5E_FRONT.format(home="").replace("[cell.tool]", BOXED_IN + "[cell.tool]"), encoding="utf-8")
    cell = load_cell(path)
    with pytest.raises(GenerateError) as caught:
        check_clearance(cell, ["ur"])
    said = str(caught.value)
    assert said.startswith("station 1 'press' pose 'approach' (nominal reading) (ur, UR5e): the ")
    assert "The home [cell.robot.home] ur = [0, -90, 90, -90, -90, 0] puts the arm in this posture" in said
    fix = re.search(r"turned half a turn about axis 1, ur = \[([^\]]*)\], every move clears", said).group(1)
    assert fix == "-180, -90, 90, -90, -90, 0"
    turned = UR5E_FRONT.format(home=f"home = {{ ur = [{fix}] }}\n").replace("[cell.tool]", BOXED_IN + "[cell.tool]")
    path.write_text(turned, encoding="utf-8")
    cell = load_cell(path)
    assert check_clearance(cell, ["ur"])
    moves = cell.kinds["station"].scene.paths(cell, ["ur"])[0].moves
    assert _elbow_z(cell.robot.arms["ur"], moves[1].joints) > 180.0 + 200.0


@pytest.mark.parametrize("name", ["agv_machine_tending", "belt_pick", "laser_tcp", "testmat_pallet"])
def test_every_bundled_cells_moves_clear_its_solids_on_its_first_arm(name):
    """The bundled cells declare their solids where their programs clear them (generate checks every target; here the
    first target with an arm, for time)."""
    cell = load_cell(EXAMPLES[name])
    target = next(t for t in cell.targets if t in cell.robot.arms)
    assert check_clearance(cell, [target])


UR5E_DIP = """[cell]
name = "ur5e_dip"
targets = ["ur"]

[cell.camera]
angle_sign = 1

[cell.limits]
max_shift_mm = 5.0
max_rotation_deg = 5.0

[cell.robot]
ur = "UR5e"
home = {{ ur = [0.0, -60.0, 60.0, 0.0, 90.0, 0.0] }}

[cell.tool]
tcp = [0.0, 0.0, 150.0, 0.0, 0.0, 0.0]
mass_kg = 1.0
cog_mm = [0.0, 0.0, 60.0]
radius_mm = 25.0

[cell.world]
floor_z_mm = {floor:.1f}

[[station]]
id = 1
name = "shelf"
mark = [250.9, -157.8, 0.0]
[station.poses]
take = [250.9, -157.8, 267.7, 57.3, 90.0, 0.0]
"""


def _tool_low(arm, tcp2flange, q, radius: float = 25.0) -> float:
    """The tool's lowest point (mm): a cylinder of radius from the flange to the TCP (forward kinematics)."""
    flange = arm.kin.fk(q)
    ends = flange[:3, 3], (flange @ tcp2flange)[:3, 3]
    axis = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
    return float(min(ends[0][2], ends[1][2]) - radius * np.sqrt(max(0.0, 1.0 - axis[2] ** 2)))


def test_the_floor_raised_into_a_joint_moves_dip_is_refused(tmp_path):
    """A UR5e whose home holds the tool up and out and whose station lies a quarter turn away about axis 1, its tool
    sideways: the joint move there (every axis linear) turns the tool down through the middle of the move, 50 mm
    below where it stands at either end (forward kinematics here). With the floor at 0 the cell generates; the floor
    raised 15 mm above the dip's lowest point (still more than the clearance under the ends) refuses that move,
    naming the tool and the floor at the middle of the move."""
    path = tmp_path / "ur5e_dip.toml"
    path.write_text(UR5E_DIP.format(floor=0.0), encoding="utf-8")
    cell = load_cell(path)
    assert check_clearance(cell, ["ur"])
    arm, tcp2flange = cell.robot.arms["ur"], cell.robot.tool.tcp2flange
    move = cell.kinds["station"].scene.paths(cell, ["ur"])[0].moves[0]
    home, take = np.asarray(cell.robot.home["ur"]), np.asarray(move.joints)
    s = np.linspace(0.0, 1.0, 401)
    low = np.array([_tool_low(arm, tcp2flange, home + v * (take - home)) for v in s])
    dip, ends = low.min(), min(low[0], low[-1])
    assert ends - dip > 45.0 and 0.3 < s[low.argmin()] < 0.7  # a dip in the middle, not an end lower than the rest
    floor = dip + 15.0
    # left to choose, generate takes another posture whose move clears the raised floor; the cell's own choice of
    # this one ([station.config.ur], authoritative) is refused for the dip
    path.write_text(UR5E_DIP.format(floor=floor), encoding="utf-8")
    assert check_clearance(load_cell(path), ["ur"])
    named = f"[station.config.ur]\ntake = [{', '.join(f'{v:.9f}' for v in take)}]\n"
    path.write_text(UR5E_DIP.format(floor=floor) + named, encoding="utf-8")
    with pytest.raises(GenerateError) as caught:
        check_clearance(load_cell(path), ["ur"])
    said = str(caught.value)
    # the move named (its number, kind and both ends), not the pose alone: both ends stand above the floor
    assert said.startswith(
        "station 1 'shelf' pose 'take' (nominal reading) (ur, UR5e): the tool dips below the floor "
        f"(cell.world.floor_z_mm = {round(floor, 1):g} mm): "
    ), said
    assert "of the joint move to it from the start (joints [0.0, -60.0, 60.0, 0.0, 90.0, 0.0] deg) (move 1 of " in said
    found = re.search(r"floor_z_mm = [0-9.]+ mm\): ([0-9.]+) mm, its lowest point at z = ([0-9.-]+) mm, at ([0-9.]+) "
                      r"of the joint move", said)
    depth, lowest, at = (float(v) for v in found.groups())
    assert 0.3 < at < 0.7
    # measured at the samples, which lie no more than half the clearance (10 mm) of travel apart: the dip's depth
    # (15 mm by forward kinematics here) is met to within that spacing, and the proof says so
    assert 15.0 - 10.0 <= depth <= 15.0 + 1e-6 and abs(lowest - (floor - depth)) < 0.06
    assert "no point of the arm travelling more than 10 mm between two" in said


# A testmat variant whose way home from the pallet sweeps a region the cycle never enters: Q moved to the arm's left
# (axis 1 at -90 deg) and the home turned between Q and the pallet (axis 1 at -45 deg), so that the cycle's move from
# home to Q turns away from the pallet and the way home's joint move from above the pallet to home crosses a sector
# the cycle passes only low, in transit between Q and the pallet.
WAY_HOME_VARIANT = (
    ('kuka = "KR 6 R900 sixx"', 'kuka = "KR 6 R900 sixx"\nhome = { kuka = [-45.0, -90.0, 90.0, 0.0, 90.0, 0.0] }'),
    ("pick = [600.0, 300.0, 50.0, 0.0, 0.0, 180.0]", "pick = [0.0, 650.0, 50.0, 0.0, 0.0, 180.0]"),
)
FENCE_MM = 40.0  # the fence's cube
CYCLE_STEP_DEG = 2.0  # the cycle's moves sampled with no axis turning more than this between samples


def _axes(bodies) -> list[tuple[str, int, np.ndarray, np.ndarray, float]]:
    """Each body as a capsule that holds it (name, link frame, segment ends in that frame, radius): the links' own, the
    tool's cylinder as the capsule along its axis, a box as the sphere about its centre."""
    from codegen.world.solids import Capsule, Cylinder

    out = []
    for body in bodies:
        shape = body.shape
        if isinstance(shape, Capsule):
            a, b, r = np.r_[shape.a, 1.0], np.r_[shape.b, 1.0], shape.radius
        elif isinstance(shape, Cylinder):
            a, b, r = np.r_[0.0, 0.0, -shape.length / 2, 1.0], np.r_[0.0, 0.0, shape.length / 2, 1.0], shape.radius
        else:
            a = b = np.r_[0.0, 0.0, 0.0, 1.0]
            r = shape.extent
        out.append((body.name, body.frame, shape.pose @ a, shape.pose @ b, float(r)))
    return out


def _nearest_cycle(arm, axes, joints: np.ndarray, points: np.ndarray) -> np.ndarray:
    """For each point, a lower bound of its distance (mm) from every body at every sampled configuration: its distance
    from the holding capsule's segment (forward kinematics) less the radius."""
    frames = arm.kin.link_frames(joints)
    least = np.full(len(points), np.inf)
    for _, frame, a, b, radius in axes:
        ends_a, ends_b = (frames[:, frame] @ a)[:, :3], (frames[:, frame] @ b)[:, :3]
        d = ends_b - ends_a
        length2 = np.maximum((d * d).sum(axis=1), 1e-12)
        t = np.clip(np.einsum("mnk,nk->mn", points[:, None] - ends_a[None], d) / length2, 0.0, 1.0)
        gap = np.linalg.norm(ends_a[None] + t[..., None] * d[None] - points[:, None], axis=2) - radius
        least = np.minimum(least, gap.min(axis=1))
    return least


@pytest.fixture(scope="module")
def way_home_fence(tmp_path_factory):
    """The variant's text, and the fence: a cube touching the body of the way home's joint move to home (from the
    pallet's first box) at the point of its middle farthest from everything the cycle sweeps. The region comes from the
    planned joints and the arm's forward kinematics, not from the proof: the cycle's moves sampled (joint moves and the
    short linear ones interpolated in joints), the way home's bodies at 0.5, 0.6 and 0.7 of the move, points on their
    holding capsules' surfaces (both ends and the middle of each segment, 26 directions)."""
    from codegen.kinds.pallet.plan import configurations
    from codegen.kinds.pallet.way_home import way_home, way_joints
    from codegen.reference import home_move
    from codegen.world.bodies import arm_bodies
    from codegen.world.cell import tool_shape

    text = EXAMPLES["testmat_pallet"].read_text(encoding="utf-8")
    for old, new in WAY_HOME_VARIANT:
        assert old in text
        text = text.replace(old, new, 1)
    path = tmp_path_factory.mktemp("fence") / "testmat_way_home.toml"
    path.write_text(text, encoding="utf-8")
    cell = load_cell(path)
    arm = cell.robot.arms["kuka"]
    pallet = cell.kinds["pallet"].section.of(cell)[0]
    cycle = cell.kinds["pallet"].scene.paths(cell, ["kuka"])[0]
    first = next(m for m in cycle.moves if m.where.endswith("target"))  # the first box's place: a stop there
    # the way home as the program plans it from there (not the proof's paths: a proof without them must fail here)
    way = way_home(cell, pallet, SimpleNamespace(name="kuka"), home_move(cell, "kuka"), first.joints, 0)
    planned = way_joints(cell, pallet, "kuka", way[:-1], first.joints, configurations(cell, pallet, "kuka"))
    axes = _axes(arm_bodies(arm, tool_shape(cell), cycle.part))
    q, sampled = np.asarray(cycle.start, dtype=float), []
    for move in cycle.moves:
        n = max(1, int(np.ceil(np.abs(move.joints - q).max() / CYCLE_STEP_DEG)))
        sampled.append(q + np.linspace(0.0, 1.0, n + 1)[:, None] * (move.joints - q))
        q = np.asarray(move.joints, dtype=float)
    above, home = np.asarray(planned[-1], dtype=float), np.asarray(cell.robot.home["kuka"], dtype=float)
    middle = above + np.array([[0.5], [0.6], [0.7]]) * (home - above)
    frames = arm.kin.link_frames(middle)
    turns = np.array([(x, y, z) for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1) if x or y or z], float)
    turns /= np.linalg.norm(turns, axis=1)[:, None]
    points, owners = [], []
    for name, frame, a, b, radius in axes:
        for f in frames[:, frame]:
            for t in (0.0, 0.5, 1.0):
                centre = (f @ (a + t * (b - a)))[:3]
                points += list(centre + radius * turns)
                owners += [name] * len(turns)
    joints = np.vstack(sampled)
    points = np.array(points)
    least = np.concatenate([_nearest_cycle(arm, axes, joints, points[i : i + 256]) for i in range(0, len(points), 256)])
    k = int(np.argmax(least))
    # between two samples no point of a body moves more than reach x the sum of the axes' turns (rad), reach: the
    # farthest any body's capsule reaches from a joint's axis (each axis passes through its link frame's origin);
    # every point between lies within half of that of a sample
    links = arm.kin.link_frames(joints)
    origins = links[:, 1:6, :3, 3]
    reach = max(
        float(np.linalg.norm((links[:, f] @ end)[:, None, :3] - origins, axis=2).max()) + r
        for _, f, a, b, r in axes for end in (a, b)
    )
    travel = reach * np.radians(np.abs(np.diff(joints, axis=0)).sum(axis=1)).max()
    return text, f"pallet 'testmat' the way home from {first.where.split(' ', 2)[2]}: home", owners[k], \
        points[k], float(least[k]), travel / 2


def test_a_fence_through_the_way_homes_route_is_refused(tmp_path, way_home_fence):
    """The variant generates; a 40 mm cube fence put where the way home's joint move from above the pallet to home
    passes (a point of one of its bodies' surfaces, computed from the planned joints: the cycle's bodies at least
    the clearance, the cube's half diagonal and the sampling's slack farther) refuses it, naming that move, the body
    and the fence; nothing written."""
    text, where, body, centre, least, slack = way_home_fence
    clearance = 20.0  # the default (docs/clearance.md)
    assert least > clearance + FENCE_MM * np.sqrt(3) / 2 + slack, (least, slack)  # the cycle passes far from it
    clear, fenced = tmp_path / "clear.toml", tmp_path / "fenced.toml"
    clear.write_text(text, encoding="utf-8")
    generated = CliRunner().invoke(main, ["generate", str(clear), "--target", "kuka", "--out", str(tmp_path / "a")])
    assert generated.exit_code == 0, generated.output
    fence = np.eye(4)
    fence[:3, 3] = centre
    world = f"[cell.world]\nsolids.fence = {{ box = [{FENCE_MM}, {FENCE_MM}, {FENCE_MM}], pose = {_pose(fence)} }}\n\n"
    fenced.write_text(text.replace("[cell.io]", world + "[cell.io]", 1), encoding="utf-8")
    out = tmp_path / "b"
    refused = CliRunner().invoke(main, ["generate", str(fenced), "--target", "kuka", "--out", str(out)])
    assert refused.exit_code == 2 and "Traceback" not in refused.output and not out.exists(), refused.output
    assert "pallet 'testmat' the way home from layer 1 box 1 target: home" in where
    assert f"{where} (kuka, KR 6 R900 sixx): the {body} touches the solid 'fence'" in refused.output, refused.output


def test_an_unstacking_box_held_at_the_start_is_proven_on_its_way_from_home_to_q(tmp_path):
    """Unstacking testmat on the UR5e: a box held at the start (a stop between the grip and Q) is carried from home to
    above Q by a joint move; with Q at the bundled place that move, in the posture the controller takes from the home,
    swings the box through the full stack: the proof refuses that posture naming the move, the part and the stack, and
    generate chooses another branch for the whole cycle (its report says so); Q moved 150 mm further off, the
    controller's own posture clears and is kept."""
    from codegen.kinds.pallet.plan import posture_note
    from codegen.kinds.pallet.reach import plan
    from codegen.kinds.pallet.scene import pallet_paths
    from codegen.world.proof import ClearanceError, prove

    text = unstacking_testmat_text()
    path = tmp_path / "testmat_unstack.toml"
    path.write_text(text, encoding="utf-8")
    cell = load_cell(path)
    pallets = cell.sections["pallet"]
    with pytest.raises(ClearanceError) as caught:
        prove(cell, pallet_paths(cell, pallets, pallets[0], "ur", plan(cell, pallets[0], "ur")))
    said = str(caught.value)
    assert said.startswith("pallet 'testmat' held box above Q (ur, UR5e): the part touches the solid 'pallet testmat: "
                           "stack below layer 5'"), said
    assert check_clearance(cell, ["ur"])
    assert "the configuration nearest the home [cell.robot.home] ur = [0, -90, 90, -90, -90, 0] does not clear" in (
        posture_note(cell, pallets[0], "ur")
    )
    path.write_text(text.replace("pick = [600.0, 300.0, 50.0,", "pick = [450.0, 350.0, 50.0,"), encoding="utf-8")
    moved = load_cell(path)
    assert check_clearance(moved, ["ur"])
    assert posture_note(moved, moved.sections["pallet"][0], "ur") == ""


def test_a_refusal_at_the_floor_prints_no_minus_zero(tmp_path):
    """Source 004's test pallet taught on the floor (its top at z = 0): the box put down would rest on the floor; the
    pallet is refused at load (codegen/kinds/pallet/room.py, tests/kinds/test_pallet_messages.py) with its numbers as
    read, never '-0.0'."""
    text = EXAMPLES["testmat_pallet"].read_text(encoding="utf-8")
    old = "origin = [650.0, -50.0, 50.0], x_point = [750.0, -50.0, 50.0], xy_point = [650.0, 30.0, 50.0]"
    assert old in text
    path = tmp_path / "floor.toml"
    path.write_text(text.replace(old, old.replace(", 50.0]", ", 0.0]")), encoding="utf-8")
    with pytest.raises(CellError) as caught:
        load_cell(path)
    said = str(caught.value)
    assert "its top (the plane of frame's origin, x_point and xy_point) is at z = 0.0 mm at its lowest corner" in said
    assert "-0.0" not in said
