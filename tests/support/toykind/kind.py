"""The toy kind: a [toy] table whose greeting a UR program says (textmsg), registered as any other distribution would
register a kind (its entry point in the group codegen.kinds)."""

from __future__ import annotations

from pathlib import Path

from codegen.protocol import Kind

PACKAGE = __name__.rpartition(".")[0]  # wherever the package is installed

KIND = Kind(
    "toy",
    order=90,
    templates=Path(__file__).parent / "templates",
    section=f"{PACKAGE}.section:ToySection",
    writer=f"{PACKAGE}.writer:ToyWriter",
    verify=f"{PACKAGE}.verify:ToyVerify",
    commands=f"{PACKAGE}.commands:ToyCommands",
)
