"""KRL dialog messages: Set_KrlDlg, Exists_KrlDlg and Clear_KrlMsg, answered by the run's simulated operator."""

from __future__ import annotations

from codegen.dialects.core.values import Record, RunError
from codegen.dialects.krl.builtins import message_text, type_name_of

# Sources: KUKA "Programming Messages" for KSS 8.2 (as transcribed by OpenKuka, docs/krl/reference/yaml/
# System.Messages.yml); KUKA's MsgLib (MsgDialog, as a public transcript shows it):
# - Set_KrlDlg(Msg: KrlMsg_T, Parameter[]: KrlMsgPar_T, Softkey[]: KrlMsgDlgSK_T, Option: KrlMsgOpt_T), every
#   parameter OUT (a variable), returns an INT handle: > 0 the dialog is shown, -1 it could not be generated; "A
#   dialog cannot be generated until no other dialog is active"; it only generates the dialog, it does not wait for
#   the answer; Option.Vl_Stop: an advance-run stop;
# - Exists_KrlDlg(handle: INT IN, Answer: INT OUT) returns BOOL: TRUE while the dialog is in the message buffer,
#   FALSE once it is answered (or deleted); Answer gets the number 1..7 of the softkey that answered it, 0 where the
#   dialog was deleted unanswered; the program polls it until FALSE;
# - KrlMsgDlgSK_T = Sk_Type (KrlMsgParType_T: #VALUE a label, #KEY a message database key, #EMPTY no softkey),
#   Sk_Txt CHAR[10]; KrlMsg_T.Modul CHAR[24], Msg_txt CHAR[80]; up to 3 parameters (%1 to %3).
# Not confirmed, modelled so: the arrays' sizes as MsgLib's MsgDialog declares them (KrlMsgPar_T[3],
# KrlMsgDlgSK_T[7]: the answers' range 1..7) are required (whether KSS refuses another size is not stated); a handle
# no dialog has (-1, or one never given) answers FALSE with Answer 0; Answer is left as it was while the dialog is
# shown. #KEY (a message database) is refused, and so is a dialog without a softkey (nothing could answer it).
# The operator (codegen/sim/operator.py, a device with press(machine, labels)) reads the dialog when the program
# first looks for its answer and presses a softkey then: that look answers TRUE, the next one FALSE with the answer.
# Without an operator, or once its answers are used, that look stops the run with a message naming the line; an
# operator who looks away once they are used (Operator.then_silent) leaves the dialog shown: TRUE at every look.
# - Clear_KrlMsg(handle: INT IN) returns BOOL: deletes the message of that handle (a public program clears its #STATE
#   message so once the awaited input came: bRes=Clear_KrlMsg(nHandle)); TRUE where it was shown. Not confirmed (the
#   manual's page was not readable here): that it deletes a dialog too, which Exists_KrlDlg then reports FALSE with
#   Answer 0 ("deleted unanswered", as above) and which no longer keeps another dialog from being generated; modelled
#   so.
SOFTKEYS = 7  # KrlMsgDlgSK_T softkeys of a dialog: answers 1..7
PARAMETERS = 3  # KrlMsgPar_T parameters, %1 to %3
SIZES = {"MODUL": 24, "MSG_TXT": 80}  # KrlMsg_T's CHAR arrays
SK_TXT_MAX = 10  # KrlMsgDlgSK_T.Sk_Txt is CHAR[10]
# Set_KrlDlg's and Exists_KrlDlg's OUT parameters (positions): each argument there must be a variable; the
# compiler writes back the ones listed in WRITTEN
OUT_PARAMETERS = {"SET_KRLDLG": (0, 1, 2, 3), "EXISTS_KRLDLG": (1,)}
WRITTEN = {"EXISTS_KRLDLG": (1,)}


class Dialog:
    """A dialog on the teach pendant: its text, its softkeys' labels (None: no key), the answer once pressed."""

    __slots__ = ("answer", "labels", "text")

    def __init__(self, text: str, labels: list[str | None]) -> None:
        self.text, self.labels, self.answer = text, labels, None


def _record(value, type_name: str, where: str, what: str) -> Record:
    if not isinstance(value, Record) or value.type != type_name:
        raise RunError(f"{where}: Set_KrlDlg: {what} is a {type_name}, got {type_name_of(value)}")
    return value


def _array(value, type_name: str, size: int, where: str, what: str) -> list:
    if not isinstance(value, list) or any(not isinstance(v, Record) or v.type != type_name for v in value):
        raise RunError(f"{where}: Set_KrlDlg: {what} is an array of {type_name}, got {type_name_of(value)}")
    if len(value) != size:
        raise RunError(f"{where}: Set_KrlDlg: {what} is a {type_name}[{size}], got {len(value)} elements")
    return value


def _label(key: Record, i: int, where: str) -> str | None:
    kind = key["SK_TYPE"]
    if kind == "#EMPTY":
        return None
    if kind == "#KEY":
        raise RunError(f"{where}: Set_KrlDlg: softkey {i}: #KEY (a message database key) is not modelled here")
    if kind != "#VALUE":
        raise RunError(f"{where}: Set_KrlDlg: softkey {i}: Sk_Type is #VALUE, #KEY or #EMPTY, got {type_name_of(kind)}")
    text = key["SK_TXT"]
    if not isinstance(text, str):
        raise RunError(f"{where}: Set_KrlDlg: softkey {i}: Sk_Txt has no text")
    if len(text) > SK_TXT_MAX:
        raise RunError(f"{where}: Set_KrlDlg: softkey {i}: Sk_Txt is CHAR[{SK_TXT_MAX}], {text!r} is longer")
    return text


def set_krldlg(fr, args, kwargs, where, setters=None):
    if len(args) != 4:
        given = len(args)
        raise RunError(f"{where}: Set_KrlDlg takes 4 arguments (message, parameters, softkeys, options), got {given}")
    msg = _record(args[0], "KRLMSG_T", where, "the message")
    params = _array(args[1], "KRLMSGPAR_T", PARAMETERS, where, "the parameters")
    keys = _array(args[2], "KRLMSGDLGSK_T", SOFTKEYS, where, "the softkeys")
    opt = _record(args[3], "KRLMSGOPT_T", where, "the options")
    for name, size in SIZES.items():
        if isinstance(msg[name], str) and len(msg[name]) > size:
            raise RunError(f"{where}: Set_KrlDlg: KrlMsg_T.{name.title()} is CHAR[{size}], the text is longer")
    labels = [_label(key, i, where) for i, key in enumerate(keys, 1)]
    if not any(labels):
        raise RunError(f"{where}: Set_KrlDlg: a dialog without a softkey (every Sk_Type #EMPTY) cannot be answered")
    if opt["VL_STOP"] is True:  # KrlMsgOpt_T.Vl_Stop: an advance-run stop
        fr.m.arrive(where)
    text = message_text(msg, params, where)
    m = fr.m
    dialogs = m.state.dialogs
    if any(d.answer is None for d in dialogs.values()):
        return -1  # another dialog is still shown: none can be generated
    m.message(text)
    handle = m.state.handle = m.state.handle + 1
    m.state.dialogs = {**dialogs, handle: Dialog(text, labels)}
    return handle


def _operator(m):
    return next((d for d in m.devices if hasattr(d, "press")), None)


def exists_krldlg(fr, args, kwargs, where, setters=None):
    if len(args) != 2:
        raise RunError(f"{where}: Exists_KrlDlg takes 2 arguments (the handle, the answer), got {len(args)}")
    handle = args[0]
    if not isinstance(handle, int) or isinstance(handle, bool):
        raise RunError(f"{where}: Exists_KrlDlg: the handle is an INT, got {type_name_of(handle)}")
    if setters is None or setters[1] is None:
        raise RunError(f"{where}: Exists_KrlDlg: the answer (OUT) is a variable")
    m = fr.m
    dialog = m.state.dialogs.get(handle)
    if dialog is None:  # no dialog has that handle: none to wait for
        setters[1](fr, 0)
        return False
    if dialog.answer is None:  # shown: the operator reads it and presses a softkey
        operator = _operator(m)
        pressed = None if operator is None else operator.press(m, dialog.labels)
        if pressed is None and getattr(operator, "then_silent", False):  # nobody answers: it stays shown
            return True
        if pressed is None:
            raise RunError(
                f"{where}: Exists_KrlDlg: the dialog {dialog.text!r} waits for the operator's answer and no operator "
                "answers in this run (codegen run --answer)"
            )
        shown = [i for i, label in enumerate(dialog.labels, 1) if label is not None]
        if isinstance(pressed, bool) or not isinstance(pressed, int) or pressed not in shown:
            keys = ", ".join(f"{i} {dialog.labels[i - 1]}" for i in shown)
            raise RunError(f"{where}: Exists_KrlDlg: the operator's answer {pressed!r} is not a softkey shown ({keys})")
        dialog.answer = pressed
        return True
    setters[1](fr, dialog.answer)
    return False


def clear_krlmsg(fr, args, kwargs, where):
    """Clear_KrlMsg(handle): the dialog (or the acknowledgement message) of that handle deleted; TRUE where one was."""
    if len(args) != 1:
        raise RunError(f"{where}: Clear_KrlMsg takes 1 argument (the handle), got {len(args)}")
    handle = args[0]
    if not isinstance(handle, int) or isinstance(handle, bool):
        raise RunError(f"{where}: Clear_KrlMsg: the handle is an INT, got {type_name_of(handle)}")
    state = fr.m.state
    if handle in state.dialogs:
        state.dialogs = {k: v for k, v in state.dialogs.items() if k != handle}
        return True
    if handle in state.waiting:
        state.waiting = {k: v for k, v in state.waiting.items() if k != handle}
        return True
    return False


# EXISTS_KRLDLG called with its setters
BUILTINS = {"SET_KRLDLG": set_krldlg, "EXISTS_KRLDLG": exists_krldlg, "CLEAR_KRLMSG": clear_krlmsg}
