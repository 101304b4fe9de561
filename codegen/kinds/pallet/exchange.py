"""The swap of a done pallet at the cell (a device of Program.run): the PLC and the fork-lift, then its reset."""

from __future__ import annotations

from dataclasses import dataclass, field

from codegen.dialects.core.values import LimitReached

# the run's end once no swap is left: the program waited that long with its done output on
SHIFT_ENDS = "the PLC swaps no more pallets: the run ends with the program waiting for the swap"


@dataclass(frozen=True)
class Swap:
    """One swap as the device saw it: the moves the program had commanded, the clock (s), the arm still moving."""

    moves: int
    clock: float
    moving: bool


@dataclass(eq=False)  # hashed by identity: its state in the run's device_state
class PalletExchange:
    """The PLC's side of a done pallet: once the program's done output has been on for swap_s (while the program
    waits), the pallet is taken away and a new one put in place (the pallet-present input off, then on), and the PLC
    raises its reset input; it drops the reset once the program turns the done output off in answer (held: it keeps
    it on). It swaps `swaps` pallets; with none left, once the done output has been on for swap_s the run ends
    (LimitReached, SHIFT_ENDS). A pallet done when the program starts is swapped the same way (the done output is on
    from the start, the time counted from the program's first wait). It knows nothing of where the arm should wait or
    what the counters should be: it logs each swap (Swap) for the plan to judge."""

    done: str  # the program's done output (on: the pallet is full, or empty)
    reset: str  # the PLC's reset input
    present: str | None  # the pallet-present input (None: the cell gives none)
    swaps: int  # how many pallets it swaps
    swap_s: float  # how long after the done output came on a swap is made (a fork-lift takes its time)
    held: bool = False  # the PLC keeps its reset on after the program's answer
    log: list[Swap] = field(default_factory=list)
    _machine: object = None

    def _state(self, machine) -> dict:
        if self._machine is not machine:  # a new run: its own log
            self._machine, self.log[:] = machine, []
        return machine.device_state.setdefault(self, {"since": None, "raised": False})

    def next_time(self, machine) -> float | None:
        state = self._state(machine)
        return None if state["since"] is None or state["raised"] else state["since"] + self.swap_s

    def on_wait(self, machine, where: str) -> bool:
        state = self._state(machine)
        done = machine.signals.get(self.done) is True
        if state["raised"]:  # the program's answer: the done output off
            if self.held or machine.signals.get(self.done) is not False:
                return False
            machine.signals[self.reset] = False
            state["raised"], state["since"] = False, None
            return True
        if not done:
            state["since"] = None
            return False
        if state["since"] is None:
            state["since"] = machine.clock
            if self.present is not None and len(self.log) < self.swaps:  # the done pallet taken away
                machine.signals[self.present] = False
                return True
            return False
        if machine.clock < state["since"] + self.swap_s:
            return False
        if len(self.log) >= self.swaps:
            raise LimitReached(SHIFT_ENDS)
        self.log.append(Swap(len(machine.trace.moves), machine.clock, bool(machine.moving)))
        if self.present is not None:
            machine.signals[self.present] = True
        machine.signals[self.reset] = True
        state["raised"] = True
        return True
