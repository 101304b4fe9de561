"""A program's files as text (decoded by the controller's encodings) and the findings of `codegen check`."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from codegen.dialects.core.values import RunError

UTF8_BOM = b"\xef\xbb\xbf"
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
    tried = " or ".join(("UTF-8", *(e for e in encodings if e.replace("_", "-").lower() not in ("utf-8", "utf8"))))
    raise RunError(f"{name}: not {tried} text (byte {first_bad})")


def read_source(path: Path, encodings: tuple[str, ...]) -> SourceFile:
    """A program file from disk (RunError with the file's name when it cannot be read or decoded)."""
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise RunError(f"{path}: cannot read: {exc.strerror or exc}") from None
    return SourceFile(str(path), decode_text(raw, str(path), encodings))
