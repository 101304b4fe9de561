"""One sign for a shown UR rotation vector at a half turn; `codegen correct` and `codegen run` print one pose text."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from codegen import poses
from codegen.cli import main

UR_DEMO = Path(__file__).resolve().parents[1] / "generated" / "agv_machine_tending" / "ur"
UR_DEMO = UR_DEMO / "agv_machine_tending.script"


def _turn(axis, angle: float) -> np.ndarray:
    """Rodrigues written out (R = cos a I + sin a [k]x + (1 - cos a) k k^T), not through codegen."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    cross = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return math.cos(angle) * np.eye(3) + math.sin(angle) * cross + (1.0 - math.cos(angle)) * np.outer(k, k)


def _lead(values) -> float:
    return next(v for v in values if abs(v) > 1e-6)


@pytest.mark.parametrize("axis", [(1, 0, 0), (0, 1, 0), (1, 0.0131, 0), (0, -1, 1), (-1, 2, 3)])
def test_either_side_of_a_half_turn_shows_one_sign(axis):
    """Turns 1e-7 rad short of and past a half turn (float32 noise) about one axis: the vector of the w >= 0
    quaternion flips its sign between the two; the shown one keeps the sign of the axis' first clear component."""
    raw_signs, shown_signs = set(), set()
    for delta in (-1e-7, -3e-8, 3e-8, 1e-7):
        rot = _turn(axis, math.pi + delta)
        raw = poses.rotvec_from_rotmat(rot)
        shown = poses.shown_rotvec(raw)
        raw_signs.add(math.copysign(1.0, _lead(raw)))
        shown_signs.add(math.copysign(1.0, _lead(shown)))
        assert np.allclose(poses.rotmat_from_rotvec(shown), rot, atol=1e-12)  # the same rotation
        assert abs(np.linalg.norm(shown) - math.pi) < 1e-6
    assert raw_signs == {1.0, -1.0}  # the rules differ here: the raw vector's sign is the noise's
    assert shown_signs == {1.0}


def test_away_from_a_half_turn_the_vector_is_kept():
    rng = np.random.default_rng(5)
    for _ in range(300):
        axis = rng.normal(size=3)
        angle = rng.uniform(0.0, math.pi - 1e-4)
        rv = axis / np.linalg.norm(axis) * angle
        assert poses.shown_rotvec(rv) == pytest.approx(tuple(rv), abs=1e-15)
    assert poses.shown_rotvec((0.0, -0.0, 0.0)) == (0.0, 0.0, 0.0)
    assert all(math.copysign(1.0, v) > 0 for v in poses.shown_rotvec((-0.0, 0.0, -0.0)))


def test_a_rotation_vector_longer_than_a_half_turn_is_shown_short():
    rv = np.array([0.0, 0.0, 1.5 * math.pi])  # 270 deg about z = 90 deg about -z
    assert np.allclose(poses.shown_rotvec(rv), (0.0, 0.0, -0.5 * math.pi), atol=1e-12)


def test_pose_text_uses_the_program_decimals():
    assert poses.pose_text((0.5, -0.0, 0.25, math.pi, 0.0, -0.0), "ur") == (
        "0.5000000 0.0000000 0.2500000 3.141592654 0.000000000 0.000000000"
    )
    assert poses.pose_text((738.5, -112.3, 305.2, 90.0, 0.0, 180.0), "xyzabc") == (
        "738.5000 -112.3000 305.2000 90.000000 0.000000 180.000000"
    )


def _correct(reading, as_json: bool):
    args = ["correct", "--station", "1", "--mark", ",".join(map(str, reading)), *(["--json"] if as_json else [])]
    out = CliRunner().invoke(main, args)
    assert out.exit_code == 0, out.output
    return out.output


def _run(reading, as_json: bool):
    names = ["input_integer_register_24", *(f"input_float_register_{n}" for n in (24, 25, 26))]
    inputs = [f"--input={n}={v}" for n, v in zip(names, (1, *reading), strict=True)]
    gripper = "--gripper=standard_digital_out[0]=standard_digital_in[1]"
    args = ["run", str(UR_DEMO), "--robot", "UR10e", "--start", "180,-90,90,-90,-90,0", "--max-moves", "4", gripper]
    args += inputs
    out = CliRunner().invoke(main, [*args, *(["--json"] if as_json else [])])
    return out.output


# Station 1's poses are a tool pointing down (c = 180 deg): every corrected pose is a half turn.
@pytest.mark.parametrize("reading", [(612.4, -285.0, 1.8), (614.0, -283.5, -1.8), (610.0, -287.0, 6.0)])
def test_correct_and_run_show_the_same_rotation_vector(reading):
    expected = {
        tuple(round(v, 4) for v in p["targets"]["ur"][:3]): p["targets"]["ur"][3:]
        for p in json.loads(_correct(reading, True))["poses"]
    }
    moves = [m["pose"] for m in json.loads(_run(reading, True))["moves"] if m["pose"] is not None]
    compared = 0
    for pose in moves:
        key = tuple(round(v, 4) for v in pose[:3])
        if key not in expected:  # home
            continue
        compared += 1
        assert abs(np.linalg.norm(pose[3:]) - math.pi) < 1e-5
        # float32 in the interpreter: the same vector to 1e-6, never its negative
        assert np.max(np.abs(np.array(pose[3:]) - expected[key])) < 1e-5, (pose, expected[key])
    assert compared >= 2


def test_correct_and_run_print_a_pose_with_the_same_decimals():
    reading = (612.4, -285.0, 1.8)
    printed = _correct(reading, False)
    shown = next(line.split()[1:7] for line in printed.splitlines() if line.strip().startswith("ur "))
    run_line = next(line for line in _run(reading, False).splitlines() if line.startswith("joint ") and "line" in line)
    values = run_line.split("):", 1)[1].split("joints")[0].split()
    assert [len(v.split(".")[1]) for v in values] == [len(v.split(".")[1]) for v in shown] == [7, 7, 7, 9, 9, 9]
