"""The simulated operator at the teach pendant: answers the program's dialogs in order, a device of Program.run."""

from __future__ import annotations

from collections.abc import Sequence


class Operator:
    """The person at the teach pendant: answers each dialog the program shows, in the order given, by pressing a
    softkey, named by its number (1, 2, ...) or by its label ("Yes", compared without case). A device of the run
    (Program.run(devices=[...]), `codegen run --answer`): it acts on nothing else. Once its answers are used it
    answers no more (the dialog waits: the interpreter stops the run with a message naming that), or, then_silent,
    looks away: a dialog stays shown for as long as the program waits on it (its own timeout then ends it)."""

    def __init__(self, answers: Sequence[int | str], then_silent: bool = False) -> None:
        self.answers = list(answers)
        self.then_silent = then_silent

    def on_wait(self, machine, where: str) -> bool:
        return False

    def next_time(self, machine) -> None:
        return None

    def press(self, machine, labels: Sequence[str | None]) -> int | str | None:
        """The softkey pressed on a dialog whose softkeys 1, 2, ... carry these labels (None: no key there): its
        number where the answer names a label shown, else the answer as given (the dialect refuses one that is
        no key shown); None: no answer left."""
        used = machine.device_state.get(self, 0)  # how many answers this run took
        if used >= len(self.answers):
            return None
        machine.device_state[self] = used + 1
        answer = self.answers[used]
        if isinstance(answer, str):
            shown = [str(label).casefold() if label is not None else None for label in labels]
            if answer.strip().isdigit():
                return int(answer.strip())
            if answer.casefold() in shown:
                return shown.index(answer.casefold()) + 1
        return answer
