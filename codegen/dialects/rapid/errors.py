"""RAPID error recovery: error numbers, RAISE, and ERROR handlers with RETRY, TRYNEXT, RETURN and RAISE."""

from __future__ import annotations

from collections.abc import Callable

from codegen.dialects.core.values import Halt, RunError, Signal, f32

# Sources (ABB, "RAPID Reference Manual" / "Technical reference manual - RAPID overview", Basic
# Characteristics - Error Recovery, and the RAISE instruction; yumpu.com/en/document/view/5679047,
# pages 109, 110, 385 and 386):
# - an error in a routine transfers control to the routine's error handler, with the system variable
#   ERRNO holding the number of the (most recent) error; the scope of the routine's data covers the handler;
# - a routine without a handler (or whose handler uses RAISE) propagates the error: it is raised again
#   where the routine was called; at the top of the call chain the system error handler reports the
#   error and stops the execution;
# - RAISE with a number is used outside a handler, with numbers 1-90; one out of range sets ERRNO to
#   ERR_ILLRAISE, which the handler can handle; RAISE without a number in a handler propagates the same
#   error to the caller's handler;
# - errors inside an error handler cannot be recovered from: they go to the system error handler.
# From the manual as recalled, not found in a text during this work (uncertain):
# - RETRY re-executes the instruction that caused the error; when it raises the error again, up to
#   four recoveries take place, then the execution stops (system parameter "No Of Retry", topic
#   Controller, type General Rapid, default 4);
# - TRYNEXT continues with the instruction after the one that caused the error; RETURN [value] returns
#   from the routine; reaching the end of the handler returns from the routine as RETURN does (a FUNC
#   then has no value: an error);
# - ERROR (errno, ...) handles only those numbers; other errors propagate as if there were no handler.
NO_OF_RETRY = 4
USER_ERRNO = range(1, 91)  # numbers a program may RAISE without booking them
BOOKED_FIRST = 500  # BookErrNo's first number (internal: the manual's range is not known here)

# The predefined error numbers this interpreter raises. Their values on the controller are not in the
# manual text found: these are distinct internal values, outside the user range 1-90 and the booked range.
ERROR_NUMBERS = {
    "ERR_DIVZERO": 1001,  # division by zero (DIV, MOD, /)
    "ERR_WAIT_MAXTIME": 1002,  # WaitUntil \MaxTime without \TimeFlag: the time ran out
    "ERR_ILLRAISE": 1003,  # RAISE with a number outside 1-90 and not booked
    # SearchL (codegen/dialects/rapid/search.py; public programs handle them by these names; one shows 1072 as
    # ERR_WHLSEARCH's value, not confirmed, so internal values here as for the others)
    "ERR_SIGSUPSEARCH": 1004,  # the searched input already has the value its flank goes to at the start
    "ERR_WHLSEARCH": 1005,  # no hit before ToPoint (or more than one with \Sup)
    "ERR_TP_MAXTIME": 1006,  # TPReadFK / TPReadNum \MaxTime without the operator's answer
    "ERR_REFUNKPRC": 1007,  # late binding (%"name"%): no procedure of that name
    "ERR_CALLPROC": 1008,  # late binding: the procedure does not take these arguments
    "ERR_ARGNOTPRESENT": 1009,  # an optional parameter read while it is not present
}
# The other predefined error numbers (errnum) of the manual, by name as recalled: the interpreter never raises them,
# but a handler may test for them (IF ERRNO = ERR_PATHDIST ...); distinct internal values from 1100 on.
_OTHER_ERRORS = """ACC_TOO_LOW ALRDYCNT ALRDY_MOVING AO_LIM ARGDUPCND ARGNAME ARGNOTPER ARGNOTVAR AXIS_ACT AXIS_IND
    AXIS_MOVING AXIS_PAR BWDLIMIT CFG_INTERNAL CFG_LIMIT CFG_ILLTYPE CFG_NOTFND CFG_OUTOFBOUNDS CNTNOTVAR CNV_NOT_ACT
    CNV_CONNECT CNV_DROPPED COLL_STOP COMM_EXT COMM_INIT DATA_RECV DEV_MAXTIME DIPLAG_LIM EXECPHR FILEACC FILEEXIST
    FILEOPEN FILNOTFND FNCNORET FRAME GO_LIM ILLDIM ILLQUAT INOISSAFE INPAR_RDONLY INT_NOTVAL INT_MAXVAL INVDIM
    IODISABLE IODN_TIMEOUT IOENABLE IOERROR LINKREF LOADED LOADID_FATAL LOADID_RETRY LOADNO_INUSE LOADNO_NOUSE
    MAXINTVAL MODULE MOD_NOT_LOADED NAME_INVALID NORUNUNIT NOT_MOVETASK NO_ALIASIO_DEF NOTARR NOTEQDIM NOTINTVAL
    NOTPRES NOTSAVED NUM_LIMIT OUTOFBND OVERFLOW PATH PATHDIST PATH_STOP PERSSUPSEARCH PID_MOVESTOP PID_RAISE_PP
    RANYBIN_CHK RANYBIN_EOF RCVDATA REFUNKDAT REFUNKFUN REFUNKTRP RMQ_DIM RMQ_FULL RMQ_INVALID RMQ_INVMSG RMQ_MSGSIZE
    RMQ_NAME RMQ_NOMSG RMQ_TIMEOUT RMQ_VALUE ROBLIMIT SC_WRITE SIG_NAME SIG_NOT_VALID SOCK_CLOSED SOCK_TIMEOUT
    SPEED_REFRESH_LIM STARTMOVE STRTOOLNG SYM_ACCESS SYMBOL_TYPE SYNCMOVEOFF SYNCMOVEON SYNTAX TASKNAME TP_DIBREAK
    TP_DOBREAK TP_NO_CLIENT TRUSTLEVEL TXTNOEXIST UDPUC_COMM UISHOW_FATAL UISHOW_FULL UNIT_PAR UNKINO UNKPROC UNLOAD
    USE_PROF WAITSYNCTASK WOBJ_MOVING"""
for _i, _name in enumerate(_OTHER_ERRORS.split()):
    ERROR_NUMBERS.setdefault(f"ERR_{_name}", 1100 + _i)
ERROR_NAMES = {number: name for name, number in ERROR_NUMBERS.items()}
ERROR_CONSTANTS = {name: f32(number) for name, number in ERROR_NUMBERS.items()}
HANDLER_END = Signal("end")  # the handler's end: leaves the routine (a FUNC without a value: an error)
HANDLER_KEY = "<error>"  # a routine frame's variable holding the error its handler is running for


class RapidError(RunError):
    """A RAPID run-time error a handler may recover from: its number, where it was raised, its text.

    internal: an error the interpreter detects (division by zero): with no handler it stays a RunError
    (the program is wrong), where an explicit error (RAISE, a timeout) stops the program as the
    controller's system error handler does. leaving: the routine frame whose handler passed it on
    (RAISE in a handler), which must not handle it again; fatal: no handler may take it."""

    def __init__(self, errno: int, message: str, name: str | None = None, internal: bool = False) -> None:
        super().__init__(message)
        self.errno = errno
        self.name = name or ERROR_NAMES.get(errno) or f"ERRNO {errno}"
        self.internal = internal
        self.leaving = None
        self.fatal = False

    def stop(self, why: str = "") -> Halt:
        """The system error handler: execution stops with the error in the event log."""
        return Halt(f"{self.name}: {self.args[0]}{why}")


def divzero(where: str) -> RapidError:
    return RapidError(ERROR_NUMBERS["ERR_DIVZERO"], f"{where}: division by zero", internal=True)


def wait_maxtime(where: str, keyword: str, seconds: float) -> RapidError:
    return RapidError(ERROR_NUMBERS["ERR_WAIT_MAXTIME"], f"{where}: {keyword} \\MaxTime {seconds:g} s passed")


def raise_error(fr, value, where: str, name: str | None) -> RapidError:
    """RAISE errno outside a handler: a number 1-90 or one BookErrNo booked; else ERR_ILLRAISE."""
    number = float(value) if not isinstance(value, bool | str) else None
    booked = fr.m.state.booked
    if number is None or number != int(number) or not (int(number) in USER_ERRNO or int(number) in booked):
        return RapidError(ERROR_NUMBERS["ERR_ILLRAISE"], f"{where}: RAISE {value}: not an error number 1-90")
    return RapidError(int(number), f"{where}: RAISE {name or int(number)}", name=name)


def book_errno(fr, where: str):
    """BookErrNo: a new error number for the program (internal range, see BOOKED_FIRST)."""
    booked = fr.m.state.booked
    number = BOOKED_FIRST + len(booked)
    fr.m.state.booked = (*booked, number)
    return f32(number)


def current_error(fr, where: str) -> RapidError:
    error = fr.vars.get(HANDLER_KEY)
    if error is None:
        raise RunError(f"{where}: RAISE without a number outside an error handler")
    return error


def protect(run: Callable, handler: Callable, errnos: Callable | None, where: str) -> Callable:
    """A statement of a routine with an ERROR handler: an error it raises runs the handler here, in the
    routine's frame; the handler's RETRY runs the statement again, TRYNEXT goes on after it, RETURN
    (or the handler's end) returns from the routine, RAISE passes the error to the caller."""

    def protected(fr):
        retries = 0
        while True:
            try:
                return run(fr)
            except RapidError as error:
                if error.fatal or error.leaving is fr or (errnos is not None and error.errno not in errnos(fr)):
                    raise
                caught, signal = error, run_handler(fr, error, handler)
            if signal is not None and signal.kind == "retry":
                retries += 1
                if retries > NO_OF_RETRY:
                    raise caught.stop(f" (RETRY: more than No Of Retry = {NO_OF_RETRY} recoveries)")
                continue
            if signal is not None and signal.kind == "trynext":
                return None
            return signal if signal is not None else HANDLER_END

    return protected


def run_handler(fr, error: RapidError, handler: Callable):
    """Run the routine's handler for error with ERRNO set; an error escaping it other than its own
    RAISE cannot be recovered from (the system error handler stops the program)."""
    fr.m.state.errno = f32(error.errno)
    outer = fr.vars.get(HANDLER_KEY)
    fr.vars[HANDLER_KEY] = error
    try:
        return handler(fr)
    except RapidError as escaped:
        if escaped.leaving is not fr:
            escaped.fatal = True
        raise
    finally:
        if outer is None:
            fr.vars.pop(HANDLER_KEY, None)
        else:
            fr.vars[HANDLER_KEY] = outer


def unhandled(error: RapidError):
    """An error no handler took, at the entry routine: the interpreter's own errors stay RunErrors;
    an explicit one stops the program with the error's name and text (the system error handler)."""
    if error.internal:
        raise RunError(error.args[0]) from None
    raise error.stop() from None
