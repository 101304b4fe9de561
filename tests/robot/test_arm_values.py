"""A custom arm's table: each bad value one message naming the key, never a Python error."""

from __future__ import annotations

import subprocess
import sys

import pytest
from support.cells import EXAMPLES

from codegen.robot.arms import ArmError, arm_from_table, catalogue

UR5E = {
    "model": "MyUR",
    "vendor": "ur",
    "family": "ur",
    "params": {"d1": 162.5, "a2": -425.0, "a3": -392.2, "d4": 133.3, "d5": 99.7, "d6": 99.6},
    "limits_deg": [[-360, 360]] * 6,
    "home_deg": [0, -90, 90, -90, -90, 0],
}


def test_the_table_as_given_is_an_arm():
    assert arm_from_table(dict(UR5E), "cell.robot.ur").family == "ur"


@pytest.mark.parametrize(
    ("change", "says"),
    [
        ({"family": ["ur"]}, "cell.robot.ur.family: expected one of opw, ur, got a list"),  # was TypeError
        ({"family": {"ur": 1}}, "cell.robot.ur.family: expected one of opw, ur, got a dict"),
        ({"params": {**UR5E["params"], "d1": 10**400}}, "cell.robot.ur.params.d1: expected a finite number, got an"),
        ({"home_deg": [0, -90, 90, -90, -90, 10**400]}, "cell.robot.ur.home_deg[5]: expected a finite number"),
        ({"payload_kg": -5.0}, "cell.robot.ur.payload_kg: expected a value in (0, 2500] kg, got -5"),
        ({"payload_kg": 10**400}, "cell.robot.ur.payload_kg: expected a finite number, got an integer of 401 digits"),
        ({"reach_mm": 0}, "cell.robot.ur.reach_mm: expected a value in (0, 10000] mm, got 0"),
    ],
)
def test_a_bad_custom_arm_names_its_key(change, says):
    with pytest.raises(ArmError) as info:
        arm_from_table({**UR5E, **change}, "cell.robot.ur")
    assert says in str(info.value)


def test_opw_offsets_are_angles_within_a_turn():
    table = {"vendor": "kuka", "model": "K", "family": "opw", "limits_deg": [[-170, 170]] * 6, "home_deg": [0] * 6}
    params = {"a1": 25, "a2": -35, "b": 0, "c1": 400, "c2": 560, "c3": 515, "c4": 80}
    assert arm_from_table({**table, "params": {**params, "offsets_deg": [0, 90, 0, 0, 0, 0]}}, "a").family == "opw"
    with pytest.raises(ArmError, match=r"a\.params\.offsets_deg: expected angles within \+-360 deg"):
        arm_from_table({**table, "params": {**params, "offsets_deg": [0, 1e9, 0, 0, 0, 0]}}, "a")


def test_every_catalogue_arm_has_a_positive_payload():
    assert all(arm.payload_kg and arm.payload_kg > 0 for arm in catalogue().values())


def test_a_list_as_family_exits_2_with_one_message(tmp_path):
    """Found by a fault probe: `family = ["ur"]` raised TypeError (unhashable list) in generate, pallet, verify."""
    text = EXAMPLES["laser_tcp"].read_text(encoding="utf-8")
    custom = (
        'ur = { model = "MyUR", family = ["ur"], params = { d1 = 162.5, a2 = -425.0, a3 = -392.2, d4 = 133.3, '
        "d5 = 99.7, d6 = 99.6 }, limits_deg = [[-360, 360], [-360, 360], [-360, 360], [-360, 360], [-360, 360], "
        "[-360, 360]], home_deg = [0, -90, 90, -90, -90, 0] }"
    )
    assert 'ur = "UR10e"' in text
    path = tmp_path / "cell.toml"
    path.write_text(text.replace('ur = "UR10e"', custom, 1), encoding="utf-8")
    proc = subprocess.run(
        [sys.executable, "-m", "codegen", "generate", str(path), "--out", str(tmp_path / "out")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "cell.robot.ur.family: expected one of opw, ur, got a list" in proc.stderr
