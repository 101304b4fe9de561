"""A dialect's state of one run beyond the program's variables: the base of each dialect's dataclass."""

from __future__ import annotations

import dataclasses


@dataclasses.dataclass
class RunState:
    """A dialect's state of one run beyond the program's variables (its system variables, handles, the motion
    under way): each dialect declares a dataclass on this in its package and its compiler makes it (new_state).
    A run starts from a copy of the state the program's set-up left (copied: its fields and the dicts, lists and
    sets they hold)."""

    def copy(self) -> RunState:
        new = object.__new__(type(self))
        new.__dict__ = {k: v.copy() if type(v) in CONTAINERS else v for k, v in self.__dict__.items()}
        return new


CONTAINERS = (dict, list, set)  # what RunState.copy copies beside the state itself
