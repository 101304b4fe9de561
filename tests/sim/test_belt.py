"""The simulated belt's devices: the count's age, the camera's trigger, the belt as a controller's mechanical unit."""

from __future__ import annotations

import numpy as np
import pytest

from codegen.sim.belt import TRIGGER_S, Belt, BeltLine, Part, TrackingUnit, UnitSettings
from codegen.sim.bus import RegisterBus

NAMES = {"seq": "s", "count": "c", "encoder": "enc", "x": "x", "z": "z", "ack": "a", "stop": "stop"}


def test_the_count_the_program_reads_is_as_old_as_the_latency():
    """A latency of 0.05 s: the count read at t is the belt's count at t - 0.05 (at 100 mm/s, 10 counts per mm:
    50 counts behind)."""
    belt = Belt(100.0, 10.0, 32)
    fresh = BeltLine(belt, [], RegisterBus(NAMES))
    late = BeltLine(belt, [], RegisterBus(NAMES), latency_s=0.05)
    assert fresh.live("enc", 2.0) - late.live("enc", 2.0) == 50


def test_the_trigger_pulses_once_per_part_at_the_camera():
    line = BeltLine(Belt(100.0, 10.0), [Part(1, 1.0, 0, 0), Part(2, 3.0, 0, 0)], RegisterBus(NAMES), trigger="di3")
    assert [line.live("di3", t) for t in (0.99, 1.0, 1.0 + TRIGGER_S / 2, 1.0 + TRIGGER_S, 3.001)] == [
        False,
        True,
        True,
        False,
        True,
    ]


def test_the_units_queue_and_position():
    """The unit counts |E| counts per mm up (whatever the counter's sign), reckons the position by its own counts
    per metre (a whole number: 8123 for 8.122679 counts per mm), connects the oldest object once it is in the
    start window and loses one that passed it; a sync within the minimum distance of the last queued one is
    not queued."""
    belt = Belt(50.0, -8.122679)
    settings = UnitSettings("CNV1", 8123, np.eye(4), start_mm=100.0, width_mm=100.0, min_gap_mm=30.0, max_mm=500.0)
    parts = [Part(1, 0.0, 0, 0), Part(2, 0.4, 0, 0), Part(3, 10.0, 0, 0)]
    unit = TrackingUnit(settings, belt, parts)
    assert unit.ignored() == {2}  # 20 mm behind part 1
    seq, due, connected = unit.connect(0.0)
    assert (seq, connected) == (1, True) and due == pytest.approx(2.0, abs=0.003)  # 100 mm at 50 mm/s, in counts
    assert unit.position_mm(3.0) == pytest.approx(150.0 * 8.122679 / 8.123, abs=0.2)
    unit.drop(3.0)
    assert unit.position_mm(3.0) == 0.0
    seq, due, connected = unit.connect(15.0)  # part 3 left the start window at 14 s: none will come
    assert seq is None and not connected


def test_a_stopped_belt_stands_for_its_interval_then_runs_on_from_where_it_stood():
    """100 mm/s, standing from 2 s to 5 s: 200 mm at 2 s and still at 4.9 s (the count too, its speed 0), 250 mm at
    5.5 s; the first moment it reaches 200 mm is 2 s, 250 mm at 5.5 s (time_at across the plateau)."""
    belt = Belt(100.0, 10.0, 16, stops=((2.0, 3.0),))
    assert [belt.travel_mm(t) for t in (1.0, 2.0, 3.5, 4.9, 5.0, 5.5)] == pytest.approx([100, 200, 200, 200, 200, 250])
    assert belt.count(2.0) == belt.count(4.9) and belt.count(5.5) - belt.count(2.0) == 500
    assert (belt.speed_at(1.0), belt.speed_at(3.0), belt.speed_at(6.0)) == (100.0, 0.0, 100.0)
    assert belt.time_at(200.0) == pytest.approx(2.0, abs=1e-9) and belt.time_at(250.0) == pytest.approx(5.5, abs=1e-9)


def test_the_line_stops_not_before_its_stop_time_when_no_part_comes():
    """With no part to come the cycle stop turns on at stop_s, not at once (a line without parts for a while)."""

    class Machine:
        clock = 0.0

    line = BeltLine(Belt(100.0, 10.0), [], RegisterBus(NAMES), stop_s=30.0)
    machine = Machine()
    assert line.next_time(machine) == 30.0 and line.on_wait(machine, "") is False
    machine.clock = 30.0
    assert line.next_time(machine) is None
