"""The pallet station in verify: the pallet taken away once the gripper closes, a supply that comes only after the
program said it waits on, the PLC answering the reset handshake (devices of Program.run)."""

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
