"""The station kind: the cell's [[station]] tables and the one program that serves them, each station by its mode."""

from __future__ import annotations

from codegen.protocol import Kind

# Stations read by a camera and served by one program per target (source 000's point correction, source 001's frame
# refinement, ...): what differs between stations is their mode's (codegen.kinds.station.mode).
KIND = Kind(
    "station",
    order=0,
    planner="codegen.kinds.station.plan:plan",
    section="codegen.kinds.station.section:SectionPart",
    writer="codegen.kinds.station.program:WriterPart",
    derivation="codegen.kinds.station.derivation:DerivationPart",
    verify="codegen.kinds.station.judge:VerifyPart",
    scene="codegen.kinds.station.scenepart:ScenePart",
    commands="codegen.kinds.station.commands:CommandsPart",
)
