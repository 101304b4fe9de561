"""What a RAPID run keeps beside the program's variables (Machine.state)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from codegen.dialects.core.runstate import RunState


@dataclass
class RapidState(RunState):
    interrupts: Any = None  # the run's interrupts.Interrupts, once one is connected
    trap: str | None = None  # the TRAP routine running now
    booked: tuple[int, ...] = ()  # the error numbers BookErrNo gave out
    errno: Any = None  # ERRNO: the most recent error's number (f32), None: no error yet
    stored_path: bool = False  # StorePath without its RestoPath yet (cycle.py)
    active: tuple | None = None  # (tooldata, wobjdata or None) of the latest move instruction
    configuration_checks: dict = field(default_factory=dict)  # "CONFJ" / "CONFL" -> on (on where not given)
    settings: dict | None = None  # motion settings as motionset.py records them (a new dict at each change)
    velset: tuple[float, float] | None = None  # VelSet: (override as a factor, the maximum TCP speed mm/s)
    pulses: dict = field(default_factory=dict)  # a digital output's pulse end time (s) by signal name
    units: dict = field(default_factory=dict)  # conveyor unit name (upper case) -> the simulated unit, activated
    saved: dict = field(default_factory=dict)  # module name (upper case) -> its data as the latest Save wrote them
