"""The toy kind's part of the cell file: [toy] greeting = "..."."""

from __future__ import annotations

from dataclasses import dataclass

from codegen import protocol
from codegen.model.schema import Key, KindKeys, Table

TOY = Table("A greeting the toy program says.", {"greeting": Key("string", "what it says", required=True)})


@dataclass(frozen=True)
class Toy:
    greeting: str


class ToySection(protocol.Section):
    keys = KindKeys(tables={"toy": Key("table", TOY.doc, table=TOY)})

    def parse(self, ctx, data: dict, cell) -> Toy | None:
        if "toy" not in data:
            return None
        table = ctx.table(data, "toy", "toy")
        ctx.no_unknown(table, set(TOY.keys), "toy")
        return Toy(ctx.name(table, "greeting", "toy.greeting"))

    def standalone(self, data: dict) -> bool:
        return "toy" in data
