"""What a URScript run keeps beside the program's variables (Machine.state)."""

from __future__ import annotations

import random
from dataclasses import dataclass, field
from typing import Any

from codegen.dialects.core.runstate import RunState

RANDOM_SEED = 0  # random(): each run draws the same numbers (a trace repeats)


@dataclass
class URScriptState(RunState):
    threads: Any = None  # the run's threads.Scheduler, once a thread runs
    speed: Any = None  # the speedl / speedj under way (motion.SpeedMode), None: none
    tcp: tuple | None = None  # set_tcp's pose (m, rotation vector rad), None: the program sets none
    payload: tuple | None = None  # Load.flat() as set_payload / set_target_payload left it
    encoders: dict = field(default_factory=dict)  # encoder index -> (decoder, input A, input B), None: disabled
    settings: dict = field(default_factory=dict)  # an installation setting's name -> (args, kwargs) last given
    flags: dict = field(default_factory=dict)  # flag number -> set_flag's value
    numbers: Any = None  # random()'s generator, made at the first call (seeded alike in every run)

    def random(self) -> random.Random:
        if self.numbers is None:
            self.numbers = random.Random(RANDOM_SEED)
        return self.numbers
