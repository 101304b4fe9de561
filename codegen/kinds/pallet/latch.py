"""The PLC's counter block (a device of Program.run): retentive memory, copied from the registers at the toggle."""

from __future__ import annotations

from dataclasses import dataclass

# what the output integer registers show before the program writes them (a robot that boots: nothing the program
# wrote; 0 as a cleared register reads)
BOOT_VALUE = 0


@dataclass(eq=False)  # hashed by identity: its state in the run's device_state
class CounterLatch:
    """The PLC's function block of one pallet's counters: its memory starts as the case's counters (what it wrote
    into the input registers); whenever the program's "counters written" toggle differs from its value at the
    block's previous look, it copies the output registers layer and box (BOOT_VALUE where the program has not written
    one) into the memory. The running bit is on throughout a run, so it copies nothing else: without the toggle the
    memory keeps the start's counters. After a run, `memory` holds the block's memory and `reported` the counters the
    program last wrote into the registers (the start's where it wrote none): the judge asks that they agree, and the
    verify checks compare the registers with the reference."""

    layer: str  # the output integer register of the layer
    box: str  # the output integer register of the box
    written: str  # the program's "counters written" toggle (an output boolean register)
    start: tuple[int, int]  # the memory at the start: the counters the case presets
    memory: tuple[int, int] = (0, 0)
    reported: tuple[int, int] = (0, 0)
    _machine: object = None

    def __post_init__(self) -> None:
        # a run that stops before its first wait leaves the memory as it started and reports nothing
        self.memory = self.reported = self.start

    def _seen(self, machine) -> dict:
        if self._machine is not machine:  # a new run: the memory as the case presets it
            self._machine, self.memory, self.reported = machine, self.start, self.start
        # the toggle as the run starts (read_output_boolean_register's value before the program writes it)
        return machine.device_state.setdefault(self, {"toggle": bool(machine.inputs.get(self.written, False))})

    def next_time(self, machine) -> None:
        self._seen(machine)
        return None

    def on_wait(self, machine, where: str) -> bool:
        # every write of a register is a wait (Machine.output_written): the block sees each one as it happens
        seen = self._seen(machine)
        names = (self.layer, self.box)
        self.reported = tuple(int(machine.outputs.get(n, s)) for n, s in zip(names, self.start, strict=True))
        toggle = bool(machine.outputs.get(self.written, False))
        if toggle != seen["toggle"]:
            seen["toggle"] = toggle
            self.memory = tuple(int(machine.outputs.get(name, BOOT_VALUE)) for name in names)
        return False
