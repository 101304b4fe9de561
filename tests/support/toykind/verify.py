"""The toy kind's verify plan: one case, in which the program says its greeting and stops nowhere."""

from __future__ import annotations

from dataclasses import dataclass

from codegen import protocol
from codegen.verify.plan import SCENARIOS, Case, Expectation, Judgement, Setup


@dataclass
class ToyFigures(protocol.Figures):
    greetings: int = 0

    def count(self, case, judged) -> None:
        self.greetings += judged

    def as_json(self) -> dict:
        return {"greetings": self.greetings}


class ToyVerify(protocol.VerifyPlan):
    scenarios = dict.fromkeys(SCENARIOS, "the toy program reads nothing and does not move")
    figures = ToyFigures

    def cases(self, cell, source, count: int, seed: int) -> list:
        return [Case("greeting")]

    def setup(self, cell, source, case):
        return Setup()

    def judge(self, cell, source, case, trace, setup):
        said = self.kind.section.of(cell).greeting in [str(m) for m in trace.messages]
        return Judgement([Expectation(None)], figures=int(said), problem=None if said else "no greeting")
