"""Safe emission: identifiers, strings, comments and numbers that cannot break a generated program."""

from __future__ import annotations

import hashlib
import re
import unicodedata
from functools import cache

from codegen import data_dir, derived
from codegen.controllers import Target, get_target
from codegen.decimals import format_literal
from codegen.dialects import get_dialect
from codegen.poses import FORMAT_DECIMALS, native_values

# Characters that may appear inside a string literal or a comment in every target: no quote, no
# backslash, no comment or statement character of any of the four languages (; ! # // %), no
# control character. Anything else becomes '?'.
SAFE_TEXT = re.compile(r"[A-Za-z0-9 _.,:+\-=/()']")
_NON_IDENT = re.compile(r"[^A-Za-z0-9]+")
_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_XML_ESCAPES = {"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&apos;"}
_TAG = re.compile(r"\{\{.*?\}\}|\{%.*?%\}|\{#.*?#\}", re.DOTALL)  # a template's expressions, statements, comments


class EmitError(Exception):
    """A cell that cannot be emitted for a target (e.g. two names that map to one identifier)."""


class Code(str):
    """Text safe to place in a program: made here (identifiers, string bodies, comments, numbers, poses,
    signals) or owned by the generator (its templates, targets/<t>.toml, the derivation: `owned`). The
    templates print nothing else (codegen/render.py refuses any other text), so a cell's value reaches a
    program only through this module. A slice or a change of case of safe text stays safe."""

    __slots__ = ()

    def __getitem__(self, key) -> Code:
        return Code(str.__getitem__(self, key))

    def upper(self) -> Code:
        return Code(str.upper(self))

    def lower(self) -> Code:
        return Code(str.lower(self))


def owned(value):
    """The generator's own text (targets/<t>.toml facts, the cached derivation, the generator's constants) marked
    as program text, through dicts, lists and tuples; never a cell's value."""
    if isinstance(value, str):
        return Code(value)
    if isinstance(value, dict):
        return {owned(k): owned(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return type(value)(owned(v) for v in value)
    return value


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


def _texts(value):
    """Every string inside a TOML value (tables, arrays)."""
    if isinstance(value, str):
        yield value
    elif isinstance(value, dict):
        for item in value.values():
            yield from _texts(item)
    elif isinstance(value, list | tuple):
        for item in value:
            yield from _texts(item)


@cache
def own_names(target_name: str) -> frozenset[str]:
    """Every identifier the generator itself writes in a program for the target: the names in the code of its
    templates (templates/<t>/**, the language's comments and strings left out, as its grammar reads them; not the
    files a program reads, such as a channel's configuration),
    in its facts (targets/<t>.toml [program] and the kinds' tables) and in the derivation's printed formulas."""
    target = get_target(target_name)
    dialect = get_dialect(target.dialect)
    quiet = [re.compile(dialect.terminal(name)) for name in ("STRING", "COMMENT") if dialect.terminal(name)]
    names: set[str] = set()
    for path in sorted((data_dir("templates") / target.name).rglob("*.j2")):
        if path.name.removesuffix(".j2").lower().endswith(dialect.configurations):  # a configuration, not code
            continue
        text = _TAG.sub(lambda m: "\x01" if m.group().startswith("{{") else "", path.read_text(encoding="utf-8"))
        for pattern in quiet:
            text = pattern.sub(" ", text)
        names.update(_IDENT.findall(text))
    for text in _texts([target.program, target.kind_tables]):
        names.update(_IDENT.findall(text))
    for block in derived.load()["printed"].get(target.dialect, {}).values():
        for text in _texts(block):
            names.update(_IDENT.findall(text))
    return frozenset(names)


@cache
def language_names(target_name: str) -> frozenset[str]:
    """The words the target's language reserves and the names its standard environment defines (predefined data,
    built-in routines and types)."""
    dialect = get_dialect(get_target(target_name).dialect)
    return dialect.keywords() | dialect.predefined()


@cache
def _keyed(target_name: str, names) -> frozenset[str]:
    """Names as the target compares identifiers (upper case where it ignores case)."""
    target = get_target(target_name)
    return frozenset(
        names(target_name) if target.identifier_case_sensitive else (n.upper() for n in names(target_name))
    )


class Emitter:
    """Per program: maps cell names to identifiers, detects collisions, formats literals. The generator's own
    names (own_names) are reserved before any of the cell's: a cell name that would take one is an EmitError
    naming both."""

    def __init__(self, target: Target) -> None:
        self.target = target
        self._taken: dict[str, str] = {}  # comparable identifier -> what it was made from
        self._own = _keyed(target.name, own_names)
        self._words = _keyed(target.name, language_names)

    def _reserved(self, ident: str) -> bool:
        """A word the language reserves or a name its standard environment defines (predefined data,
        built-in routines and types)."""
        return self._key(ident) in self._words

    def _key(self, ident: str) -> str:
        return ident if self.target.identifier_case_sensitive else ident.upper()

    def reserve(self, ident: str, origin: str = "generator") -> Code:
        """Register an identifier the generator itself uses (a name of its own, never a cell's)."""
        key = self._key(ident)
        if key not in self._own:
            self._claim(ident, origin)
        return Code(ident)

    def identifier(self, prefix: str, name: str, origin: str) -> Code:
        """prefix + the name mapped to [A-Za-z0-9_], shortened with a hash to the target's limit; a name
        that would start with a digit gets a letter first, one that is a word the language reserves or a
        name it predefines gets a "_" after it, so that every accepted name is a valid identifier."""
        ident = mapped_name(prefix, name, self.target.identifier_max)
        if ident[0].isdigit():
            ident = mapped_name(f"n{prefix}", name, self.target.identifier_max)
        if self.target.identifier_case == "upper":
            ident = ident.upper()
        if self._reserved(ident):
            ident = ident[: self.target.identifier_max - 1] + "_"
        self._claim(ident, origin)
        return Code(ident)

    def signal(self, value, origin: str) -> Code:
        """A digital signal as the cell names it for this controller: a number, or the name of a configured
        signal, written as it is (the controller's I/O configuration defines it: no mapping), so a name the
        language reserves or defines, or one of the program's own, is refused (EmitError naming both)."""
        if isinstance(value, int) and not isinstance(value, bool):
            return Code(str(value))
        return self.given_name(value, origin, "signal")

    def given_name(self, value, origin: str, what: str) -> Code:
        """A name of something the controller has (a configured signal, another program's data such as a
        production tool), written as it is: a name the language reserves or defines, or one of the program's
        own, is refused (EmitError naming both)."""
        if not isinstance(value, str) or not _IDENT.fullmatch(value) or len(value) > self.target.identifier_max:
            raise EmitError(f"{self.target.name}: {origin}: {value!r} is not a {what} name the program can use")
        if self._reserved(value):
            raise EmitError(
                f"{self.target.name}: {origin}: {value!r} is a word or predefined name of {self.target.title}; "
                f"the program cannot name a {what} so"
            )
        self._claim(value, origin)
        return Code(value)

    def numbered(self, pattern: str, n, origin: str) -> Code:
        """The controller's numbered data (a pattern of the target's facts around a whole number: TOOL_DATA[{n}])."""
        if isinstance(n, bool) or not isinstance(n, int):
            raise EmitError(f"{self.target.name}: {origin}: {n!r} is not a whole number")
        return Code(pattern.format(n=n))

    def signal_ref(self, direction: str, value, origin: str) -> Code:
        """The signal as the program reads or sets it ("input" or "output"): the target's pattern around it."""
        return Code(self.target.program["signals"][direction].format(n=self.signal(value, origin)))

    def _claim(self, ident: str, origin: str) -> None:
        key = self._key(ident)
        if key in self._own:
            raise EmitError(
                f"{self.target.name}: {origin} and the program's own name {ident} both map to the identifier "
                f"{ident}; rename the cell's"
            )
        if key in self._taken and self._taken[key] != origin:
            raise EmitError(
                f"{self.target.name}: {origin} and {self._taken[key]} both map to the identifier {ident}; rename one"
            )
        self._taken[key] = origin

    def string(self, text: str) -> Code:
        """Body of a string literal (quotes added by the template), within the target's limit."""
        return Code(safe_text(text, self.target.string_max))

    def comment(self, text: str) -> Code:
        return Code(safe_text(text, 120))

    @staticmethod
    def xml_text(text: str) -> Code:
        """Character data or an attribute value of an XML file a program reads (a channel's configuration): the
        text XML-escaped, every character outside printable ASCII '?' (the file stays ASCII)."""
        return Code("".join(_XML_ESCAPES.get(ch, ch) if " " <= ch <= "~" else "?" for ch in text))

    @staticmethod
    def number(value: float, decimals: int) -> Code:
        return Code(format_literal(value, decimals))

    @staticmethod
    def figure(value: float) -> Code:
        """A number in its shortest form, for prose (comments, messages): 2.5, 1e+06."""
        return Code(f"{float(value):g}")

    def pose(self, pose) -> list[Code]:
        """A taught pose's numbers in the target's pose format, each with that format's decimals."""
        fmt = self.target.pose_format
        values = native_values(pose.values, pose.pose_format, fmt)
        return [Code(format_literal(v, d)) for v, d in zip(values, FORMAT_DECIMALS[fmt], strict=True)]
