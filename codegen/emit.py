"""Safe emission: identifiers, strings, comments and numbers that cannot break a generated program."""

from __future__ import annotations

import hashlib
import re
import unicodedata

from codegen.controllers import Target
from codegen.decimals import format_literal
from codegen.dialects import get_dialect
from codegen.poses import FORMAT_DECIMALS, native_values

# Characters that may appear inside a string literal or a comment in every target: no quote, no
# backslash, no comment or statement character of any of the four languages (; ! # // %), no
# control character. Anything else becomes '?'.
SAFE_TEXT = re.compile(r"[A-Za-z0-9 _.,:+\-=/()']")
_NON_IDENT = re.compile(r"[^A-Za-z0-9]+")


class EmitError(Exception):
    """A cell that cannot be emitted for a target (e.g. two names that map to one identifier)."""


def safe_text(text: str, limit: int | None = None) -> str:
    """Printable ASCII from SAFE_TEXT only; other characters become '?'; '//' is broken up."""
    out = "".join(ch if SAFE_TEXT.fullmatch(ch) else "?" for ch in _fold(text))
    out = out.replace("//", "/?")
    if limit is not None and len(out) > limit:
        out = out[: limit - 3] + "..."
    return out


def _fold(text: str) -> str:
    """Drop accents where a plain letter exists (e -> e); other non-ASCII stays and is replaced."""
    out = []
    for ch in text:
        if ch.isascii():
            out.append(ch)
            continue
        base = unicodedata.normalize("NFKD", ch).encode("ascii", "ignore").decode("ascii")
        out.append(base if len(base) == 1 and base.isalnum() else "\x00")
    return "".join(out)


FOLDER_MAX = 64  # a cell's folder under generated/: its name, shortened like an identifier


def mapped_name(prefix: str, name: str, limit: int) -> str:
    """prefix + the name mapped to [A-Za-z0-9_], shortened with a hash of the name to `limit`."""
    base = _NON_IDENT.sub("_", _fold(name).replace("\x00", "_")).strip("_") or "x"
    ident = f"{prefix}{base}"
    if len(ident) > limit:
        digest = hashlib.sha256(name.encode("utf-8")).hexdigest()[:4]
        ident = f"{ident[: limit - 5].rstrip('_')}_{digest}"
    return ident


def folder_name(name: str) -> str:
    """The folder of a cell under the output directory: its name in [a-z0-9_], target-independent."""
    return mapped_name("", name, FOLDER_MAX).lower()


class Emitter:
    """Per program: maps cell names to identifiers, detects collisions, formats literals."""

    def __init__(self, target: Target) -> None:
        self.target = target
        self._taken: dict[str, str] = {}  # comparable identifier -> what it was made from

    def _reserved(self, ident: str) -> bool:
        keywords = get_dialect(self.target.dialect).keywords()  # as the dialect's grammar names them
        return ident in keywords or ident.upper() in keywords

    def _key(self, ident: str) -> str:
        return ident if self.target.identifier_case_sensitive else ident.upper()

    def reserve(self, ident: str, origin: str = "generator") -> str:
        """Register an identifier the generator itself uses."""
        self._claim(ident, origin)
        return ident

    def identifier(self, prefix: str, name: str, origin: str) -> str:
        """prefix + the name mapped to [A-Za-z0-9_], shortened with a hash to the target's limit; a name
        that would start with a digit gets a letter first, one that is a word the language reserves
        gets a "_" after it, so that every accepted name is a valid identifier."""
        ident = mapped_name(prefix, name, self.target.identifier_max)
        if ident[0].isdigit():
            ident = mapped_name(f"n{prefix}", name, self.target.identifier_max)
        if self.target.identifier_case == "upper":
            ident = ident.upper()
        if self._reserved(ident):
            ident = ident[: self.target.identifier_max - 1] + "_"
        self._claim(ident, origin)
        return ident

    def _claim(self, ident: str, origin: str) -> None:
        key = self._key(ident)
        if key in self._taken and self._taken[key] != origin:
            raise EmitError(
                f"{self.target.name}: {origin} and {self._taken[key]} both map to the identifier {ident}; rename one"
            )
        self._taken[key] = origin

    def string(self, text: str) -> str:
        """Body of a string literal (quotes added by the template), within the target's limit."""
        return safe_text(text, self.target.string_max)

    def comment(self, text: str) -> str:
        return safe_text(text, 120)

    @staticmethod
    def number(value: float, decimals: int) -> str:
        return format_literal(value, decimals)

    def pose(self, pose) -> list[str]:
        """A taught pose's numbers in the target's pose format, each with that format's decimals."""
        fmt = self.target.pose_format
        values = native_values(pose.values, pose.pose_format, fmt)
        return [format_literal(v, d) for v, d in zip(values, FORMAT_DECIMALS[fmt], strict=True)]
