"""The rules a finding can break: verify's checks (told from the words of a mismatch) and check's codes, each with
a short name and its help text."""

from __future__ import annotations

import re
from dataclasses import dataclass


@dataclass(frozen=True)
class Rule:
    id: str
    name: str
    help: str


# verify: (rule, words that tell a mismatch of it, help); the first whose words match names the mismatch
VERIFY = (
    (
        "verify/run-error",
        r"^run error",
        "The program stopped with an error of the controller's language (or ran past "
        "the step limit) where the reference expects it to go on.",
    ),
    (
        "verify/stop",
        r"expected a stop|stop message|unexpected stop",
        "The program stops where the reference goes on, "
        "goes on where the reference stops (a reading out of limits, an unknown station), or stops with another "
        "message.",
    ),
    ("verify/move-count", r"\d+ moves, expected \d+", "The run makes more or fewer moves than the reference plans."),
    (
        "verify/motion",
        r"\) is (joint|linear|circular)",
        "A move is of another motion type (joint, linear) than planned.",
    ),
    (
        "verify/pose",
        r"position error",
        "A move ends away from the reference's pose (float64, 4x4 matrices) by more "
        "than the target's tolerance (float32 controllers: 0.005 mm, 0.001 deg).",
    ),
    (
        "verify/joints",
        r"ends at joints",
        "The arm reaches the pose with other joints (another configuration or turn) than the controller's rule gives.",
    ),
    ("verify/payload", r"payload", "The payload in force at a move (mass, centre of gravity) is not the cell's."),
    ("verify/tool", r"tool in force", "The tool in force at a move (its TCP) is not the cell's."),
    ("verify/joints", r"joints are not known", "The arm's joints at a move could not be solved."),
    (
        "verify/move-setting",
        r"^move \d+ \([^)]*\): \S+ ",
        "A move's speed, zone, tool, base or other setting is not the one the target's facts and the plan ask for.",
    ),
    (
        "verify/output",
        r"^output ",
        "A digital output is set out of the planned order, to another value, after "
        "another move, while the arm moves, or not at all.",
    ),
    (
        "verify/stored",
        r" holds .* when the program ends",
        "A value the program keeps for later programs (a counter, a stored result) differs from the reference's.",
    ),
    ("verify/log", r"^log line|^logged ", "A number the program writes to its log differs from the reference's."),
    (
        "verify/kind",
        r"",
        "The program kind's own judgement of the run (its device protocol, its figures) found a "
        "difference from the reference.",
    ),
)
VERIFY_PATTERNS = tuple((rule, re.compile(words)) for rule, words, _ in VERIFY)
EDIT = Rule(
    "verify/edit",
    "hand edit",
    "A line of a given program differs from the program the cell generates: "
    "generated programs are changed through the cell file and `codegen generate`, not by hand.",
)

CELL_ERROR = Rule(
    "plant/cell",
    "cell not done",
    "The cell could not be verified or checked: its file does not load, a pose is out of reach, or its programs are "
    "missing or do not load (the message says which). Its other findings are not known.",
)

# check: the codes of `codegen check` (Finding.code) and what each means
CHECK = {
    "syntax": "The file does not parse in the controller's language.",
    "load": "The program cannot be loaded: a file missing, a data list without its program, or what loading refuses.",
    "files": "The files given do not make a program (a data file without its program file).",
    "error": "An error the controller's compiler reports.",
    "type": "A value of the wrong data type (assignment, argument, condition, index, operator).",
    "arguments": "A routine called with the wrong number or kind of arguments.",
    "unsupported": "A construct or built-in the interpreter does not model: the program is not checked past it.",
    "undefined-name": "A name read but never declared or assigned in the program.",
    "undefined-function": "A function called that neither the program nor the language defines.",
    "undefined-routine": "A routine called that none of the program's modules defines.",
    "unknown-type": "A data type the language does not know.",
    "thread-called": "A thread called like a function (a thread is started with run).",
    "wait-without-timeout": "A wait on an input without a timeout: the program hangs for ever if the input never "
    "comes.",
    "motion-before-tcp": "A move before the program sets its TCP: the arm moves with whatever TCP the controller "
    "holds.",
    "motion-before-tool-base": "A move before the program sets its tool and base: the arm moves with whatever the "
    "controller holds.",
    "speed-over-arm": "A joint speed the program states is over the arm's fastest joint.",
    "speed": "A speed the program states is over the arm's limit.",
    "tool": "A move with the flange as tool (tool0) although the program has its own tool.",
    "wobj": "A move with a work object declared without a value.",
    "work-object": "A move's work object is not set as the program's others are.",
    "predefined": "The program's own data under the name of the controller's predefined data.",
    "name-too-long": "A name longer than the controller allows.",
    "name-length": "A name longer than the controller allows.",
    "output-in-advance-run": "An output set while the advance run is ahead of the arm: it switches before the arm "
    "has arrived.",
    "approximation-lost": "An approximated (blended) move whose blend the following statement cancels.",
    "module-attribute": "A module attribute the controller does not know.",
    "implicit-signal": "A signal used without a declaration (the controller's configuration must define it).",
    "signal-kind": "A signal used as another kind (digital, analog, group) than it is.",
    "no-main": "No main routine: the task cannot start from the program pointer's usual place.",
}


def verify_rule(problem: str) -> str:
    """The rule of a verify mismatch's problem (its words as the checks write them)."""
    return next(rule for rule, pattern in VERIFY_PATTERNS if pattern.search(problem))


def rule(rule_id: str) -> Rule:
    """The rule of an id: verify's, or check's (check/<code>); a check code without a help text of its own is
    described by its code."""
    for known, _, text in VERIFY:
        if known == rule_id:
            return Rule(known, known.split("/", 1)[1], text)
    for known in (EDIT, CELL_ERROR):
        if rule_id == known.id:
            return known
    code = rule_id.split("/", 1)[1]
    text = CHECK.get(code, f"A finding of codegen check ({code}).")
    return Rule(rule_id, code, text)
