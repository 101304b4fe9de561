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
    after late_s, within the program's timeout; "sealed": see SealedCup). It starts closed from the previous cycle: the
    feedback on (verify's start state)."""

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

    def let_go(self, t: float, on: bool) -> float | None:
        """The first moment from t on at which the feedback reads off (on: the feedback at the start, before the first
        change it made); None: never."""
        for when, value in self.changes:
            if when <= t + 1e-9:
                on = value
            elif not on:
                break
            elif not value:
                return when
        return None if on else t

    def on_wait(self, machine: Machine, where: str) -> bool:
        if self.feedback is None:
            return False
        out = machine.signals.get(self.output)
        if out is not None and out != self._seen:
            self._seen, on = out, out == self.value
            blocked = (on and self.behaviour == "silent") or (not on and self.behaviour == "stuck")
            delay = self.late_s if self.behaviour == "late" else GRIPPER_S
            self._due = None if blocked else (machine.clock + delay, on)
        return self._answer(machine)

    def _answer(self, machine: Machine) -> bool:
        """The feedback's change that is due by now, made (True: a signal changed)."""
        if self._due is not None and machine.clock >= self._due[0]:
            machine.signals[self.feedback] = self._due[1]
            self.changes.append(self._due)
            self._due = None
            return True
        return False


@dataclass
class SealedCup(Gripper):
    """A suction cup whose vacuum reaches its switch only as the program gives up on the grip (the late hold's limit:
    the feedback never reads on while the output is on): the output off closes the valve with the cup sealed on the
    part, so the feedback reads on from that moment and the cup holds the part until the vacuum has decayed, late_s
    later (the feedback off). The device answers a read of its feedback at once (a switch's state, not the program's
    next wait), so a program that reads it right after its output sees the part still held."""

    behaviour: str = "sealed"
    _machine: Machine | None = None

    def on_wait(self, machine: Machine, where: str) -> bool:
        self._machine = machine
        if self.feedback is None:
            return False
        out = machine.signals.get(self.output)
        if out is not None and out != self._seen:
            tried, self._seen = self._seen == self.value, out
            if tried and out != self.value and not machine.signals.get(self.feedback):
                machine.signals[self.feedback] = True
                self.changes.append((machine.clock, True))
                self._due = (self._off_at(machine) + self.late_s, False)
                return True
        return self._answer(machine)

    def let_go(self, t: float, on: bool) -> float | None:
        """The cup holds a part it was sealed on until the vacuum has decayed (late_s after the output off at t),
        whether or not the program waited long enough for the device to show it."""
        return t + self.late_s

    def _off_at(self, machine: Machine) -> float:
        """When the program set the output off (the device may see it only at the program's next wait or read)."""
        return next((o.time for o in reversed(machine.trace.outputs) if o.name == self.output), machine.clock)

    def live(self, name: str, t: float):
        """Nothing of its own (None): the feedback as the device last set it, once it has seen the output now."""
        if name == self.feedback and self._machine is not None:
            self.on_wait(self._machine, "read")
        return None
