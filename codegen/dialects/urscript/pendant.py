"""URScript's Yes/No question on the teach pendant: request_boolean_from_primary_client, the run's operator answers."""

from __future__ import annotations

from codegen.dialects.core.values import RunError, describe
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


def request_boolean_from_primary_client(fr, args, kwargs, where):
    message = arguments(NAME, ("message",), {}, args, kwargs, where)["message"]
    if not isinstance(message, str):
        raise RunError(f"{where}: {NAME}: the message is a string, got {describe(message)}")
    if not message:
        raise RunError(f"{where}: {NAME}: the message cannot be empty (URScript manual)")
    if len(message) > STRING_MAX:
        raise RunError(f"{where}: {NAME}: the message is longer than {STRING_MAX} characters")
    m = fr.m
    m.message(message)
    operator = next((d for d in m.devices if hasattr(d, "press")), None)
    pressed = None if operator is None else operator.press(m, BUTTONS)
    if pressed is None:
        raise RunError(
            f"{where}: {NAME}: the program waits for the operator's answer to {message!r} and no operator answers "
            "in this run (codegen run --answer Yes or --answer No)"
        )
    if isinstance(pressed, bool) or pressed not in (1, 2):
        raise RunError(f"{where}: {NAME}: the operator's answer {pressed!r} is not a button shown (1 Yes, 2 No)")
    return pressed == 1


def builtins() -> dict:
    return {NAME: request_boolean_from_primary_client}
