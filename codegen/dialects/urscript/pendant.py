"""URScript's questions on the teach pendant (Yes/No, entry fields): the run's operator answers."""

from __future__ import annotations

from codegen.dialects.core.values import RunError, describe, f32
from codegen.dialects.urscript.io import STRING_MAX
from codegen.dialects.urscript.values import arguments

# Source: Universal Robots, "The URScript Programming Language", e-Series, Script Directory, 17. Module interfaces,
# 17.72 request_boolean_from_primary_client(message) (as a public transcript of the manual shows it):
# "Request input from operator. Polyscope shows dialog box with "yes" and "no" buttons. Function blocks until
# operator selects option on the Polyscope screen. NOTE: Operator can also stop program by pressing "Cancel"
# button"; message: "A string with a message shown on Polyscope dialog box. Can not be empty."; return value:
# "True or False: Value selected by the operator". The request_float/_integer/_string_from_primary_client pages
# (17.73-17.75) say the same with an entry field.
# Not confirmed: the PolyScope release that brought the function (the transcript names none); what the controller
# does with an empty message (refused here, as the manual says it cannot be); the dialog's buttons' exact labels
# (the manual writes "yes" and "no"; the operator's answer is compared without case anyway).
# Modelled: the message goes to the trace's messages; the run's simulated operator (codegen/sim/operator.py, a
# device with press(machine, labels), `codegen run --answer`) presses button 1 Yes (True) or 2 No (False), named by
# number or label. Without an operator, or once its answers are used, the run stops with a message naming the line
# (the program would wait there). "Cancel" (stopping the program) is not modelled: that answer is refused.
BUTTONS = ("Yes", "No")  # the dialog's buttons 1 and 2: True, False
NAME = "request_boolean_from_primary_client"


def _ask(fr, name: str, args, kwargs, where, labels, hint: str):
    """Show the question's message and take the run's operator's answer (a RunError where none comes)."""
    message = arguments(name, ("message",), {}, args, kwargs, where)["message"]
    if not isinstance(message, str):
        raise RunError(f"{where}: {name}: the message is a string, got {describe(message)}")
    if not message:
        raise RunError(f"{where}: {name}: the message cannot be empty (URScript manual)")
    if len(message) > STRING_MAX:
        raise RunError(f"{where}: {name}: the message is longer than {STRING_MAX} characters")
    m = fr.m
    m.message(message)
    operator = next((d for d in m.devices if hasattr(d, "press")), None)
    answer = None if operator is None else operator.press(m, labels)
    if answer is None:
        raise RunError(
            f"{where}: {name}: the program waits for the operator's answer to {message!r} and no operator answers "
            f"in this run (codegen run --answer {hint})"
        )
    return answer


def request_boolean_from_primary_client(fr, args, kwargs, where):
    pressed = _ask(fr, NAME, args, kwargs, where, BUTTONS, "Yes or --answer No")
    if isinstance(pressed, bool) or pressed not in (1, 2):
        raise RunError(f"{where}: {NAME}: the operator's answer {pressed!r} is not a button shown (1 Yes, 2 No)")
    return pressed == 1


def entry(kind: str):
    """request_integer / _float / _string_from_primary_client: the operator types the answer in the dialog's
    entry field (the manual's pages 17.73-17.75); the run's operator's answer is taken as that text."""
    name = f"request_{kind}_from_primary_client"

    def ask(fr, args, kwargs, where):
        answer = _ask(fr, name, args, kwargs, where, (), "VALUE")
        text = str(answer).strip()
        if kind == "string":
            return str(answer)
        try:
            return int(text) if kind == "integer" else f32(float(text))
        except ValueError:
            raise RunError(f"{where}: {name}: the operator's answer {answer!r} is not {ENTRY_WORDS[kind]}") from None

    return ask


ENTRY_WORDS = {"integer": "an integer", "float": "a number"}


def builtins() -> dict:
    entries = {f"request_{kind}_from_primary_client": entry(kind) for kind in ("integer", "float", "string")}
    return {NAME: request_boolean_from_primary_client, **entries}
