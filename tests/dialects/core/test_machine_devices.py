"""The machine's devices: which of them answer a live input, plan a time or act at a wait."""

from __future__ import annotations

from codegen.dialects.core.machine import Machine


class _Plain:
    """A device with no plans and no live inputs: it only acts when the program waits."""

    def __init__(self) -> None:
        self.waits = 0

    def on_wait(self, machine: Machine, where: str) -> bool:
        self.waits += 1
        return False


class _Timed(_Plain):
    def __init__(self, due: float | None) -> None:
        super().__init__()
        self.due = due

    def next_time(self, machine: Machine) -> float | None:
        return self.due


class _Live(_Plain):
    def __init__(self, values: dict) -> None:
        super().__init__()
        self.values = values

    def live(self, name: str, t: float):
        return self.values.get(name)


def test_the_earliest_planned_time_of_the_devices_that_plan_one():
    machine = Machine(None, {}, 100, (_Plain(), _Timed(None), _Timed(2.5), _Timed(0.75), _Timed(4.0)))
    assert machine.next_device_time() == 0.75
    assert Machine(None, {}, 100, (_Plain(), _Timed(None))).next_device_time() is None


def test_a_live_input_from_the_first_device_that_has_it_else_the_signals():
    devices = (_Plain(), _Live({"a": 3}), _Live({"a": 4, "b": 5}))
    machine = Machine(None, {}, 100, devices)
    machine.signals["c"] = True
    assert (machine.input_signal("a"), machine.input_signal("b"), machine.input_signal("c")) == (3, 5, True)
    assert machine.input_signal("d", "off") == "off"


def test_every_device_sees_each_wait():
    devices = (_Plain(), _Timed(1.0), _Live({}))
    machine = Machine(None, {}, 100, devices)
    assert machine.wait("x:1:1") is False
    assert [d.waits for d in devices] == [1, 1, 1]
    assert Machine(None, {}, 100).wait("x:1:1") is False
