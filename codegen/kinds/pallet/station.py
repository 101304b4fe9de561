"""The pallet station in verify (devices of Program.run): the pallet taken away, a late supply, the PLC's reset
handshake (also while the operator is asked), a box lost from the gripper."""

from __future__ import annotations

from dataclasses import dataclass

from codegen.dialects.core.machine import Machine


@dataclass
class PalletTaken:
    """The pallet-present input goes off at the first wait after the program sets the gripper's output to grip (the
    arm at the pick place, or on the pallet when unstacking) and stays off: the pallet was taken away meanwhile."""

    output: str  # the gripper's output
    value: bool  # the output's value that closes the gripper
    present: str  # the pallet-present input

    def next_time(self, machine: Machine) -> float | None:
        return None

    def on_wait(self, machine: Machine, where: str) -> bool:
        if machine.signals.get(self.present) is False or machine.signals.get(self.output) != self.value:
            return False
        machine.signals[self.present] = False
        return True


@dataclass
class SupplyLate:
    """A supply (discharge) input that stays off until the program has told the operator it waits on it (its
    notification among the run's messages), then comes on: a gap in the line longer than the program's timeout."""

    signal: str  # the interlock's input
    message: str  # the notification the program shows when the wait lasted its timeout

    def next_time(self, machine: Machine) -> float | None:
        return None

    def on_wait(self, machine: Machine, where: str) -> bool:
        if machine.signals.get(self.signal) or self.message not in machine.trace.messages:
            return False
        machine.signals[self.signal] = True
        return True


@dataclass
class ResetAnswered:
    """The PLC's side of the counter reset: it holds the reset input on until the program turns the pallet's done
    output off (the program's answer), then drops it. It knows nothing of the counters: whether the program reset
    them, and only after that answer, is the plan's to judge."""

    reset: str  # the PLC's reset input
    done: str  # the pallet's done output

    def next_time(self, machine: Machine) -> float | None:
        return None

    def on_wait(self, machine: Machine, where: str) -> bool:
        if not machine.signals.get(self.reset) or machine.signals.get(self.done) is not False:
            return False
        machine.signals[self.reset] = False
        return True


@dataclass(eq=False)  # hashed by identity: its state in the run's device_state
class ResetWhileAsked:
    """The PLC's reset input comes on once the program shows the operator its question (nobody answers it): the
    PLC's handshake, not the operator, says the pallet is new. ResetAnswered then drops it in answer."""

    reset: str  # the PLC's reset input
    question: str  # the question's text as the program shows it

    def next_time(self, machine: Machine) -> float | None:
        return None

    def on_wait(self, machine: Machine, where: str) -> bool:
        if machine.device_state.get(self) or self.question not in machine.trace.messages:
            return False
        machine.device_state[self] = True
        machine.signals[self.reset] = True
        return True


@dataclass
class BoxLost:
    """The box slips out of the gripper on its way: once the arm was commanded a move after the device first saw the
    grip confirmed (the lift), the feedback input reads off while the output still says grip, and stays off.
    Whether the program notices before it counts the box as placed is the plan's to judge."""

    output: str  # the gripper's output
    value: bool  # the output's value that closes the gripper
    feedback: str  # the gripper's feedback input
    _held_at: int | None = None  # the moves commanded when the device first saw the grip confirmed
    _machine: Machine | None = None

    def next_time(self, machine: Machine) -> float | None:
        return None

    def on_wait(self, machine: Machine, where: str) -> bool:
        self._machine = machine
        held = machine.signals.get(self.output) == self.value and machine.signals.get(self.feedback)
        if self._held_at is None and held:
            self._held_at = len(machine.trace.moves)
        return False

    def live(self, name: str, t: float):
        """The feedback as the program reads it: off once the box is lost (None: the other devices' value)."""
        if name != self.feedback or self._held_at is None or self._machine is None:
            return None
        return False if len(self._machine.trace.moves) > self._held_at else None
