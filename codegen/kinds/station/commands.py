"""The station kind's commands: each mode's."""

from __future__ import annotations

from codegen import protocol
from codegen.kinds.station.mode import modes


class CommandsPart(protocol.Commands):
    def commands(self) -> list:
        return [command for mode in modes().values() for command in mode.commands()]
