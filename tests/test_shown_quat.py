"""One sign for a shown quaternion: the rule itself, and `codegen correct` and `codegen run` showing the same one."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from codegen import poses
from codegen.cli import main

ABB_DEMO = Path(__file__).resolve().parents[1] / "generated" / "agv_machine_tending" / "abb" / "agv_machine_tending.mod"


def _half_turn(axis) -> np.ndarray:
    """The rotation by 180 deg about axis, written out (R = 2 k k^T - I), not through a quaternion."""
    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    return 2.0 * np.outer(k, k) - np.eye(3)


@pytest.mark.parametrize("axis", [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (0, -1, 1), (-1, 2, 3)])
def test_a_half_turn_shows_one_sign_whatever_the_float32_noise(axis):
    exact = _half_turn(axis)
    rng = np.random.default_rng(7)
    shown = set()
    for _ in range(40):
        noisy = exact + rng.uniform(-2e-7, 2e-7, (3, 3))  # float32 rounding of a pose (1.2e-7 per unit)
        q = poses.quat_from_rotmat(noisy)
        lead = next(v for v in q if abs(v) > poses.QUAT_SIGN_TIE)
        assert lead > 0
        shown.add(tuple(np.sign(np.round(q, 4))))
    assert len(shown) == 1, shown
    # The axis component that decides: the first non-zero one of the axis, made positive.
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    first = next(v for v in k if v != 0)
    assert np.allclose(poses.quat_from_rotmat(exact), [0.0, *(k * math.copysign(1.0, first))], atol=1e-12)


def test_away_from_a_half_turn_w_is_positive():
    rng = np.random.default_rng(3)
    for _ in range(200):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        if abs(q[0]) < 1e-3:
            continue
        shown = poses.shown_quat(-q if q[0] > 0 else q)
        assert shown[0] > 0 and np.allclose(np.abs(shown), np.abs(q))
        assert np.allclose(poses.rotmat_from_quat(shown), poses.rotmat_from_quat(q), atol=1e-12)


def test_shown_quat_never_shows_minus_zero():
    assert all(math.copysign(1.0, v) > 0 for v in poses.shown_quat((-0.0, -0.0, -1.0, -0.0)))


def _correct_abb(reading) -> dict:
    out = CliRunner().invoke(main, ["correct", "--station", "1", "--mark", ",".join(map(str, reading)), "--json"])
    assert out.exit_code == 0, out.output
    shown = [p["targets"]["abb"] for p in json.loads(out.output)["poses"]]
    return {tuple(round(v, 2) for v in pose[:3]): pose[3:] for pose in shown}


def _run_abb(reading) -> list[list[float]]:
    names = ("VIS_STATION=1", "VIS_X={}", "VIS_Y={}", "VIS_THETA={}")
    inputs = [n.format(v) for n, v in zip(names, (1, *reading), strict=True)]
    args = ["run", str(ABB_DEMO), "--start", "0,0,0,0,90,30", "--max-moves", "4", "--json"]
    out = CliRunner().invoke(main, [*args, *(f"--input={i}" for i in inputs)])
    return [m["pose"] for m in json.loads(out.output)["moves"] if m["pose"] is not None]


@pytest.mark.parametrize("reading", [(612.4, -285.0, 1.8), (614.0, -283.5, -1.8), (610.0, -287.0, 6.0)])
def test_correct_and_run_show_the_same_quaternion(reading):
    expected = _correct_abb(reading)
    moves = _run_abb(reading)
    assert moves
    for pose in moves:
        key = tuple(round(v, 2) for v in pose[:3])
        assert key in expected, (key, sorted(expected))
        # float32 in the interpreter: the same quaternion to 1e-6, never its negative
        assert np.max(np.abs(np.array(pose[3:]) - expected[key])) < 1e-5, (pose, expected[key])


def test_correct_prints_no_minus_zero():
    out = CliRunner().invoke(main, ["correct", "--station", "1", "--mark", "612.4,-285,1.8"])
    assert out.exit_code == 0
    assert "-0.0000" not in out.output and "phi 0.0000 deg" in out.output
