"""What the second first-hour walk (a fresh clone, the README and the docs only: a UR5e tending a lathe, a KUKA
pallet cell) stumbled on, each with the cell as the walk wrote it."""

from __future__ import annotations

import pytest

from codegen.model.cell import load_cell

LATHE = """\
[cell]
name = "lathe_tending"
targets = ["ur"]
pose_format = "xyzabc"

[cell.camera]
angle_sign = 1

[cell.robot]
ur = "UR5e"

[cell.tool]
tcp = [0.0, 0.0, 160.0, 0.0, 0.0, 0.0]
mass_kg = 1.1
cog_mm = [0.0, 0.0, 60.0]
radius_mm = 30.0

[cell.limits]
max_shift_mm = 15.0
max_rotation_deg = 5.0

[[station]]
id = 7
name = "lathe"
mark = [520.0, -180.0, 0.5]
[station.poses]
approach = [540.0, -120.0, 380.0, 0.0, 0.0, 180.0]
chuck = [560.0, -110.0, 260.0, 0.0, 0.0, 180.0]
"""


def test_a_configuration_change_prints_the_joints_rounded(write_cell):
    """With the chuck pose left out, the station's retreat changes configuration for a reading: the refusal printed
    both joint sets with 16 digits each ("153.5271831256482, -81.93119270557679, ..."); now to 0.1 deg."""
    from codegen.generate import GenerateError, check_envelope

    cell = load_cell(write_cell(LATHE.replace("chuck = [560.0, -110.0, 260.0, 0.0, 0.0, 180.0]\n", "")))
    with pytest.raises(GenerateError) as info:
        check_envelope(cell, None)
    said = str(info.value)
    assert (
        "pose 'retreat' (ur, UR5e): the arm would change configuration (taught [153.5, -81.9, 66.2, -74.3, -90.0, "
        "243.5], here [" in said
    )
    assert "153.527" not in said
