"""The toy kind: a [toy] table whose greeting a UR program says (textmsg), registered as any other distribution would
register a kind (its entry point in the group codegen.kinds)."""

from __future__ import annotations

from pathlib import Path

from codegen.protocol import Kind

KIND = Kind(
    "toy",
    order=90,
    templates=Path(__file__).parent / "templates",
    section="tests.support.toykind.section:ToySection",
    writer="tests.support.toykind.writer:ToyWriter",
    verify="tests.support.toykind.verify:ToyVerify",
    commands="tests.support.toykind.commands:ToyCommands",
)
