"""A program's files as text (decoded by the controller's encodings) and the findings of `codegen check`."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from codegen.dialects.core.values import RunError
from codegen.readfile import ReadError, read_regular

UTF8_BOM = b"\xef\xbb\xbf"
FRESH = "<fresh>/"  # the name prefix of a program file rendered from the cell rather than read from disk
SEVERITIES = ("error", "unsupported", "warning")  # a finding's weight: check's exit 2 for the first two, 1 else


@dataclass(frozen=True)
class SourceFile:
    """One file of a program: its name (a path as given, for messages) and its decoded text."""

    name: str
    text: str

    @property
    def suffix(self) -> str:
        return Path(self.name).suffix.lower()

    @property
    def stem(self) -> str:
        return Path(self.name).stem.lower()


@dataclass(frozen=True)
class Finding:
    """What `codegen check` reports of a place in a program: file, line and column (1-based; 0: the whole
    file), a short code naming the rule (e.g. "syntax", "undefined-name", "wait-without-timeout") and one
    sentence without Python names."""

    file: str
    line: int
    column: int
    severity: str  # one of SEVERITIES
    code: str
    message: str

    def text(self) -> str:
        where = self.file if self.line <= 0 else f"{self.file}:{self.line}:{self.column}"
        return f"{where}: {self.severity}: {self.message} [{self.code}]"

    def as_json(self) -> dict:
        return {
            "file": self.file,
            "line": self.line,
            "column": self.column,
            "severity": self.severity,
            "code": self.code,
            "message": self.message,
        }


@dataclass(frozen=True)
class CheckOptions:
    """What `codegen check` knows beyond the files (Dialect.check_files(files, options)): the arm the program is
    for (codegen.robot.arms.Arm, from --robot; None: a language's checks that need the arm's limits take the
    controller family's documented limits, or are skipped where there are none) and the routine it starts at
    (--entry, where the language lets a program start at a routine of its own: None, its main)."""

    arm: object | None = None
    entry: str | None = None


PLACE = re.compile(r"^(?P<file>.+?):(?P<line>\d+)(?::(?P<column>\d+))?: (?P<message>.*)$", re.DOTALL)
NOT_MODELLED = ("is not modelled", "not modelled here", "unsupported")


def finding_of(error: Exception | str, files: list, code: str = "load") -> Finding:
    """A Finding from a RunError's message "file:line:column: message" (the file one of `files`, SourceFile or
    names; else the first), severity "unsupported" where the message says what is not modelled, else "error"."""
    text = str(error)
    names = [getattr(f, "name", f) for f in files]
    file, line, column, message = names[0] if names else "", 0, 0, text
    for name in sorted(names, key=len, reverse=True):  # a known file's name first (it may hold a colon)
        if text.startswith(name + ":"):
            rest = PLACE.match("x:" + text[len(name) + 1 :])
            if rest is not None:
                file, line, column, message = name, int(rest["line"]), int(rest["column"] or 0), rest["message"]
            else:
                file, message = name, text[len(name) + 1 :].strip()
            break
    else:
        match = PLACE.match(text)
        if match is not None:
            file, line, column, message = match["file"], int(match["line"]), int(match["column"] or 0), match["message"]
        elif text.startswith(file + ":"):
            message = text[len(file) + 1 :].strip()
    severity = "unsupported" if any(words in message for words in NOT_MODELLED) else "error"
    if message.startswith("syntax error"):
        code = "syntax"
    return Finding(file, line, column, severity, "unsupported" if severity == "unsupported" else code, message)


def decode_text(raw: bytes, name: str, encodings: tuple[str, ...]) -> str:
    """A program file's bytes as text: UTF-8 (a byte-order mark dropped), else each of the controller's
    other encodings in turn (a Windows-1252 controller backup); a RunError naming the file and the first
    byte no encoding reads. Line ends are normalised to \\n."""
    if raw.startswith(UTF8_BOM):
        raw = raw[len(UTF8_BOM) :]
    first_bad = None
    for encoding in ("utf-8", *(e for e in encodings if e.replace("_", "-").lower() not in ("utf-8", "utf8"))):
        try:
            text = raw.decode(encoding)
        except UnicodeDecodeError as exc:
            first_bad = exc.start if first_bad is None else first_bad
            continue
        return text.replace("\r\n", "\n").replace("\r", "\n")
    others = [e for e in encodings if e.replace("_", "-").lower() not in ("utf-8", "utf8")]
    if not others:  # a controller whose programs are UTF-8 only
        raise RunError(f"{name}: not UTF-8 text (byte {first_bad}): this controller's programs are UTF-8")
    tried = ", ".join(("UTF-8", *others))
    raise RunError(f"{name}: byte {first_bad} is not text in any encoding this controller uses ({tried})")


PROGRAM_FILE_MAX_BYTES = 16 << 20  # the largest generated program (a cell of 1,000 stations) is a few MB
PROGRAM_LINE_MAX = 10_000  # characters on one line; the longest generated line is under 1,000


def read_source(path: Path, encodings: tuple[str, ...]) -> SourceFile:
    """A program file from disk, read as a cell file is (codegen.readfile: a regular file only, within a size
    bound) with a bound on any one line; RunError with the file's name when it cannot be read or decoded."""
    try:
        raw = read_regular(
            path,
            PROGRAM_FILE_MAX_BYTES,
            "a program file",
            "a program that large is no controller's (the largest generated one is a few MB)",
        )
    except ReadError as exc:
        raise RunError(str(exc)) from None
    text = decode_text(raw, str(path), encodings)
    for number, line in enumerate(text.split("\n"), start=1):
        if len(line) > PROGRAM_LINE_MAX:
            raise RunError(f"{path}: line {number}: longer than {PROGRAM_LINE_MAX:,} characters; no program's line is")
    return SourceFile(str(path), text)
