"""A large program's globals shared by its runs: each run's stores are logged and undone when it ends."""

# A run starts from the globals its program's data made (Program._prepare). Copying them for every run costs
# what the program has (4,000 globals at 1,000 stations: 40-95 us a run, more than some runs take); a program
# with that many shares one dict instead: a store records the value it replaces the first time, and the run's
# end puts every replaced value back (values are never changed in place: a list or a record is replaced
# whole, so what the run kept or traced stays as it was). Reads are the dict's own.

from __future__ import annotations

ABSENT = object()
SHARE_FROM = 1000  # globals: fewer are copied per run (a copy of a few hundred costs less than logged stores)


class SharedGlobals(dict):
    """A dict whose stores are logged until undo()."""

    __slots__ = ("log",)

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.log: dict = {}

    def _note(self, key) -> None:
        if key not in self.log:
            self.log[key] = dict.get(self, key, ABSENT)

    def __setitem__(self, key, value) -> None:
        if key not in self.log:
            self.log[key] = dict.get(self, key, ABSENT)
        dict.__setitem__(self, key, value)

    def __delitem__(self, key) -> None:
        self._note(key)
        dict.__delitem__(self, key)

    def setdefault(self, key, default=None):
        if key not in self:
            self[key] = default
        return dict.__getitem__(self, key)

    def pop(self, key, *default):
        if key in self:
            self._note(key)
        return dict.pop(self, key, *default)

    def update(self, *args, **kwargs) -> None:
        for key, value in dict(*args, **kwargs).items():
            self[key] = value

    def popitem(self):
        raise TypeError("a program's shared globals do not pop items")

    def clear(self) -> None:
        raise TypeError("a program's shared globals are not cleared")

    def undo(self) -> None:
        """Every value the run replaced put back, every global it made removed."""
        for key, value in self.log.items():
            if value is ABSENT:
                dict.pop(self, key, None)
            else:
                dict.__setitem__(self, key, value)
        self.log.clear()
