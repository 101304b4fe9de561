"""A station's part, pick to place: [station.gripper] and `fixed` in the cell file, the program's start with or
without a part, and verify following the part through a run (codegen/kinds/station/part.py)."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest
from support import stations

from codegen.dialects.core.trace import SignalEvent, Trace
from codegen.guard import NO_PART, PART_HELD, halt_message
from codegen.kinds.station.cases import Case, accepted_traces
from codegen.kinds.station.part import part_problem
from codegen.kinds.station.point.reference import Reading
from codegen.kinds.station.section import stations_of
from codegen.model.cell import CellError, cell_from_dict, load_cell

DEMO = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "agv_machine_tending.toml"


def _demo() -> dict:
    return tomllib.loads(DEMO.read_text(encoding="utf-8"))


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda s: s["gripper"].update(spindle="grip"), r"station\[0\]\.gripper\.spindle: not a pose of the station"),
        (
            lambda s: s["gripper"].update(chuck="drop"),
            r"station\[0\]\.gripper\.chuck: expected one of 'grip', 'release' \(what the gripper does there\)",
        ),
        (lambda s: s["gripper"].pop("tray_done"), r"station\[0\]\.gripper\.tray_raw: grip after grip at 'chuck_out'"),
        (lambda s: s["gripper"].pop("tray_raw"), r"station\[0\]\.gripper\.chuck: release after release"),
        (lambda s: s.update(fixed=["tray", "tray_raw"]), r"station\[0\]\.fixed\[0\]: not a pose of the station"),
        (lambda s: s.update(fixed=["chuck"]), r"station\[0\]\.fixed\[0\]: 'chuck' is the work pose"),
    ],
)
def test_a_bad_gripper_or_fixed_key_names_itself(edit, message):
    data = _demo()
    edit(data["station"][0])
    with pytest.raises(CellError, match=message):
        cell_from_dict(data, "cell.toml")


def test_a_gripper_without_feedback_is_refused():
    data = _demo()
    del data["cell"]["io"]["feedback"]
    with pytest.raises(CellError, match=r"station\[0\]\.gripper: the gripper needs \[cell\.io\] with its feedback"):
        cell_from_dict(data, "cell.toml")


def test_the_start_decides_by_what_the_station_does_first():
    """A station that takes a part first, started with one in the gripper, stops at home (the part is not dropped
    there); one that puts a part down first, started empty, stops too; the others go on."""
    cell = load_cell(DEMO)
    lathe = stations_of(cell)[0]
    reading = Reading(lathe.id, *lathe.spec.mark)
    (held,), _ = accepted_traces(cell, Case("part_held", reading, held=True))
    assert (held.status, held.reason, held.moves) == ("halt", PART_HELD, ())
    (empty,), _ = accepted_traces(cell, Case("zero_shift", reading))
    assert empty.status == "ok" and len(empty.moves) == len(lathe.path)
    placing = cell_from_dict(_place_first(), "cell.toml")
    station = stations_of(placing)[0]
    (none,), _ = accepted_traces(placing, Case("part_held", Reading(station.id, *station.spec.mark), held=False))
    assert none.reason == NO_PART
    assert halt_message(cell, NO_PART, None, 0) != halt_message(cell, PART_HELD, None, 0)


def _place_first() -> dict:
    """The demo with its first station putting down a part it is given: the chuck loaded with the part carried in."""
    data = _demo()
    data["station"][0]["gripper"] = {"chuck": "release"}
    return data


@pytest.mark.parametrize("target", ["ur", "kuka", "abb", "dtrans"])
def test_the_part_cases_pass_on_every_target(target):
    """Started with the part the station does not expect, every program stops at home with the message; with the
    gripper silent or stuck it stops at the first grip or release; a place-first station carries its part in."""
    for data in (_demo(), _place_first()):
        cell = cell_from_dict(data, str(DEMO))
        cases = [c for c in stations.build_cases(cell, 1, 3) if c.reading.station_id == 1]
        assert {"part_held", "gripper_silent", "gripper_stuck", "zero_shift"} <= {c.category for c in cases}
        row = stations.verify(cell, stations.source(cell, target), cases)
        assert row.mismatches == 0, row.first_mismatches


def _event(value: bool, xyz, moving: bool = False) -> SignalEvent:
    pose = np.eye(4)
    pose[:3, 3] = xyz
    return SignalEvent("grip", value, 10, 0.0, moving, 3, pose)


class _Move:
    def __init__(self, name: str, xyz) -> None:
        self.pose_name = name
        self.tcp2base = np.eye(4)
        self.tcp2base[:3, 3] = xyz


def _problem(events, held: bool = False):
    cell = load_cell(DEMO)
    station = stations_of(cell)[0]
    moves = [_Move("chuck_out", (700.0, 0.0, 300.0)), _Move("tray_done", (500.0, -400.0, 250.0))]
    trace = Trace(outputs=events)
    return part_problem(cell, "grip", station, moves, held, trace, 0.005)


def test_the_part_followed_from_grip_to_release():
    assert _problem([_event(False, (0, 0, 900)), _event(True, (700, 0, 300)), _event(False, (500, -400, 250))]) is None
    dropped = _problem([_event(True, (700, 0, 300)), _event(False, (500, -400, 370))])
    assert dropped.startswith("the gripper opened with a part at (500.000, -400.000, 370.000) mm")
    assert "not put down at a release pose (tray_done)" in dropped
    moving = _problem([_event(True, (700, 0, 300)), _event(False, (500, -400, 250), moving=True)])
    assert "while the arm moves" in moving
    assert "no part is taken there" in _problem([_event(True, (700, 0, 310))])
    # a part held at the start, opened at home: dropped where the cycle starts
    assert "the part is dropped there" in _problem([_event(False, (0, 0, 900))], held=True)
    # gripped again on the part it holds: nothing changes, and it is put down at its place
    assert _problem([_event(True, (0, 0, 900)), _event(False, (500, -400, 250))], held=True) is None


BENCH = DEMO.parent / "thermometer_bench.toml"


def _bench_carrying() -> dict:
    """The frame-mode bench as two runs: the tray station takes a thermometer (and carries it home), the bath
    station (a frame station) puts it into the cavity: a station that releases first, started with its part."""
    data = tomllib.loads(BENCH.read_text(encoding="utf-8"))
    data["cell"]["io"] = _demo()["cell"]["io"]
    data["station"][0]["gripper"] = {"cavity": "release"}
    data["station"][1]["gripper"] = {"slot": "grip"}
    return data


@pytest.mark.parametrize("target", ["ur", "kuka", "abb", "dtrans"])
def test_a_part_carried_from_one_station_into_a_frame_station(target):
    cell = cell_from_dict(_bench_carrying(), str(BENCH))
    assert [s.holds_at_start for s in stations_of(cell)] == [True, False]
    cases = [c for c in stations.build_cases(cell, 1, 3) if c.category != "unknown_station"]
    assert {c.category for c in cases} >= {"part_held", "gripper_silent", "gripper_stuck"}
    row = stations.verify(cell, stations.source(cell, target), cases)
    assert row.mismatches == 0, row.first_mismatches
