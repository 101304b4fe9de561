"""The simulated gripper (or a machine's clamp): its feedback follows the program's output, a device of Program.run."""

from __future__ import annotations

from dataclasses import dataclass, field

from codegen.dialects.core.machine import Machine

GRIPPER_S = 0.02  # how long the simulated gripper takes to confirm (less than one poll)


@dataclass
class Gripper:
    """A gripper (or a machine's clamp) beside the controller, a device of Program.run: GRIPPER_S after
    the program sets the output to the value, the feedback input turns on; after it sets the other
    value, off ("silent": it never turns on; "stuck": it never turns off; "late": it confirms each action only
    after late_s, within the program's timeout). It starts closed from the previous cycle: the feedback on
    (verify's start state)."""

    output: str
    feedback: str | None
    value: bool = True
    behaviour: str = "prompt"
    late_s: float = GRIPPER_S
    changes: list = field(default_factory=list)  # (time, value) of each change of the feedback it made
    _due: tuple | None = None  # (time, feedback then)
    _seen: object = None  # the output's value the device last acted on

    def next_time(self, machine: Machine) -> float | None:
        return None if self._due is None else self._due[0]

    def on_wait(self, machine: Machine, where: str) -> bool:
        if self.feedback is None:
            return False
        out = machine.signals.get(self.output)
        if out is not None and out != self._seen:
            self._seen, on = out, out == self.value
            blocked = (on and self.behaviour == "silent") or (not on and self.behaviour == "stuck")
            delay = self.late_s if self.behaviour == "late" else GRIPPER_S
            self._due = None if blocked else (machine.clock + delay, on)
        if self._due is not None and machine.clock >= self._due[0]:
            machine.signals[self.feedback] = self._due[1]
            self.changes.append(self._due)
            self._due = None
            return True
        return False
