"""generate's fast grammar check (codegen/dialects/core/recognize.py) says what lark's parse says."""

from __future__ import annotations

import random
import re
from pathlib import Path

import pytest

from codegen.dialects import dialects
from codegen.dialects.core.larkdoor import terminals
from codegen.dialects.core.parsing import grammar_parser, open_grammar
from codegen.dialects.core.recognize import Recognizer
from codegen.generate import GenerateError, check_rendered
from codegen.render import RenderedFile

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"


def _interpreter(dialect) -> str:
    return dialect.module("interpreter").__file__


def _programs(dialect) -> list[Path]:
    suffixes = dialect.suffixes + dialect.companions
    return sorted(p for p in GENERATED.rglob("*") if p.suffix.lower() in suffixes)


def _lark_parses(dialect, text: str) -> bool:
    try:
        grammar_parser(_interpreter(dialect), False).parse(text)
    except Exception:
        return False
    return True


DIALECTS = sorted(
    name
    for name, dialect in dialects().items()
    if (Path(__import__(dialect.__module__, fromlist=["_"]).__file__).parent / "grammar.lark").exists()
)


@pytest.mark.parametrize("name", DIALECTS)
def test_every_bundled_program_is_recognized(name):
    dialect = dialects()[name]
    recognizer = Recognizer(grammar_parser(_interpreter(dialect), False))
    programs = _programs(dialect)
    assert programs
    for path in programs:
        assert recognizer.accepts(path.read_text(encoding="utf-8")), path


def _mutations(text: str, rng: random.Random, words: list[str]):
    """Small edits of a valid program, most of them breaking it: a line dropped, doubled or moved,
    a character dropped, a word of the language put somewhere, two lines' halves swapped."""
    lines = text.splitlines(keepends=True)
    for _ in range(40):
        edited = list(lines)
        i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
        kind = rng.randrange(6)
        if kind == 0:
            del edited[i]
        elif kind == 1:
            edited.insert(j, edited[i])
        elif kind == 2:
            edited.insert(j, edited.pop(i))
        elif kind == 3 and len(edited[i]) > 2:
            k = rng.randrange(len(edited[i]) - 1)
            edited[i] = edited[i][:k] + edited[i][k + 1 :]
        elif kind == 4:
            k = rng.randrange(len(edited[i]))
            edited[i] = edited[i][:k] + " " + rng.choice(words) + " " + edited[i][k:]
        else:
            a, b = edited[i], edited[j]
            edited[i] = a[: len(a) // 2] + b[len(b) // 2 :]
        yield "".join(edited)


@pytest.mark.parametrize("name", DIALECTS)
def test_edited_programs_get_lark_verdict(name):
    """Each edit of each dialect's demo program: the recognizer accepts exactly what lark parses,
    with one recognizer (and its memo of chunks) for all of them, as generate uses it."""
    dialect = dialects()[name]
    parser = grammar_parser(_interpreter(dialect), False)
    recognizer = Recognizer(parser)
    words = sorted({w for w in dialect.keywords()} | {"(", ")", "[", "]", ",", "=", ":=", ";", "1.5", '"x"'})
    rng = random.Random(16)
    programs = [p for p in _programs(dialect) if "agv_machine_tending" in p.parts or "belt_pick" in p.parts]
    verdicts = []
    for path in programs:
        for text in _mutations(path.read_text(encoding="utf-8"), rng, words):
            verdict = _lark_parses(dialect, text)
            assert recognizer.accepts(text) == verdict, (path.name, text)
            verdicts.append(verdict)
    assert True in verdicts and False in verdicts  # the edits include programs lark parses and refuses


def _terminals(dialect):
    return terminals(grammar_parser(_interpreter(dialect), False))


@pytest.mark.parametrize("name", DIALECTS)
def test_grammar_spells_digits_as_a_class(name):
    """The recognizer's memo key writes every digit as 0: sound only while no terminal tells one
    digit from another (a keyword with a digit, a class like [1-9], a count {2})."""
    for terminal, regexp, _ in _terminals(dialects()[name]):
        rest = regexp.replace("\\d", "").replace("0-9", "")
        assert not re.search(r"[0-9]", rest), (terminal, regexp)


@pytest.mark.parametrize("name", DIALECTS)
def test_only_white_space_crosses_a_line_break(name):
    """The recognizer lexes each chunk (up to a run of white space holding a line break) alone:
    sound only while no other terminal can match a line break, start with white space or look behind."""
    for terminal, regexp, ignored in _terminals(dialects()[name]):
        if terminal == "_NL" or (ignored and re.fullmatch(regexp, " \t")):
            continue  # the white space itself
        assert not re.fullmatch(regexp, "\n \n\t"), terminal
        assert "(?<" not in regexp, (terminal, regexp)  # looks behind its start, across a chunk's start
        for space in " \t\f\r\n":  # starts with white space: it could begin in the run that ends a chunk
            match = re.match(regexp, space + "x1")
            assert match is None or not match.group(0).startswith(space), (terminal, regexp)
        inside = re.sub(r"\[\^[^\]]*(\\n|\n)[^\]]*\]", "", regexp)  # classes that exclude the line break
        assert not re.search(r"\n|\\n|\\s|\\W|\\D|\[\^|\(\?s", inside), (terminal, regexp)


def test_generate_check_refuses_a_broken_program():
    """The check still refuses: a program with one line doubled in the wrong place, named by lark."""
    text = (GENERATED / "agv_machine_tending" / "ur" / "agv_machine_tending.script").read_text(encoding="utf-8")
    broken = text.replace("\nend\n", "\nend\nend\n", 1)
    files = [RenderedFile("agv_machine_tending/ur/agv_machine_tending.script", broken)]
    says = r"ur/agv_machine_tending.script: generated program does not parse: .*:\d+:\d+: syntax error"
    with pytest.raises(GenerateError, match=says):
        check_rendered(files)
    check_rendered([RenderedFile("agv_machine_tending/ur/agv_machine_tending.script", text)])


@pytest.mark.parametrize("name", DIALECTS)
def test_tree_starts_are_larks(name):
    """The interpreter's parser sets only where each tree starts (larkdoor.start_positions): the same line
    and column as lark's propagate_positions, for every tree of every bundled program."""
    dialect = dialects()[name]
    ours = grammar_parser(_interpreter(dialect), True)
    larks = open_grammar(_interpreter(dialect), propagate_positions=True)
    compared = 0
    for path in _programs(dialect):
        text = path.read_text(encoding="utf-8")
        for mine, theirs in zip(ours.parse(text).iter_subtrees(), larks.parse(text).iter_subtrees(), strict=True):
            assert mine.data == theirs.data
            assert mine.meta.empty == theirs.meta.empty, (path.name, mine.data)
            if not theirs.meta.empty:
                assert (mine.meta.line, mine.meta.column) == (theirs.meta.line, theirs.meta.column), (path, mine)
                compared += 1
    assert compared > 1000
