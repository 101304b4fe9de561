"""What codegen prints is inert: control characters, escape sequences and bidirectional overrides shown escaped."""

from __future__ import annotations

import io
import re
import sys
from collections.abc import Iterator
from contextlib import contextmanager

# C0 controls but tab and newline (ESC starts every terminal escape sequence, CR overwrites a line), DEL, the C1
# controls (CSI, OSC), lone surrogates (a file name's undecodable bytes), and the format characters that hide,
# join or reorder text: soft hyphen, Arabic letter mark, Mongolian vowel separator, zero-width marks, the line and
# paragraph separators, the bidirectional embeddings, overrides and isolates, invisible operators, the byte order
# mark, interlinear annotations and the tag characters (Unicode general categories Cc, Cf, Cs, Zl, Zp)
UNSAFE = re.compile(
    "[\x00-\x08\x0b-\x1f\x7f-\x9f\u00ad\u061c\u180e\u200b-\u200f\u2028-\u202e\u2060-\u206f"
    "\ud800-\udfff\ufeff\ufff9-\ufffb\U000e0000-\U000e007f]"
)


def inert(text: str) -> str:
    """`text` with every character that could change what a terminal does or shows replaced by its escape
    (`\\x1b`, `\\u202e`), as Python writes it in a string literal."""
    return UNSAFE.sub(_escaped, text)


def _escaped(match: re.Match) -> str:
    code = ord(match.group())
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}"


class InertStream(io.TextIOBase):
    """A text stream that passes everything written through `inert` to the stream it wraps."""

    def __init__(self, stream):
        self.wrapped = stream

    def write(self, text: str) -> int:
        self.wrapped.write(inert(text))
        return len(text)

    def flush(self) -> None:
        self.wrapped.flush()

    def isatty(self) -> bool:
        return self.wrapped.isatty()

    def fileno(self) -> int:
        return self.wrapped.fileno()

    def writable(self) -> bool:
        return True

    @property
    def encoding(self) -> str:
        return getattr(self.wrapped, "encoding", None) or "utf-8"

    @property
    def errors(self) -> str | None:
        return getattr(self.wrapped, "errors", None)


@contextmanager
def inert_output() -> Iterator[None]:
    """While it lasts, everything printed to stdout and stderr goes through `inert`: the one door of every
    printer, the command's messages, click's own errors and a warning alike."""
    saved = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = InertStream(sys.stdout), InertStream(sys.stderr)
    try:
        yield
    finally:
        sys.stdout, sys.stderr = saved


def own_controls(stream):
    """The stream beneath the door, for codegen's own terminal controls (a progress bar's redraws) only: what
    they show from a cell or a program must go through `inert` first."""
    return stream.wrapped if isinstance(stream, InertStream) else stream
