"""A program given to verify beside the one the cell generates: the lines changed, what they change in a run."""

from __future__ import annotations

import difflib
import math
import re
from collections import Counter
from pathlib import Path

import numpy as np

from codegen.decimals import format_literal
from codegen.dialects.core.trace import Trace, halt_text
from codegen.dialects.core.values import RunError
from codegen.verify.checks import TOLERANCES, Checker
from codegen.verify.plan import SCENARIOS
from codegen.verify.programs import ProgramSource, fresh_sources
from codegen.verify.report import setting_names

EDIT_CASES = 16  # cases each program and its generated twin run: the kind's first category (one a station), from home
SHOWN_LINES = 8  # changed lines named per program (the rest counted)
TIME_STEP_S = 1e-6  # a clock difference below this is the same time (both clocks sum the same float64 terms)


def edits(cell, sources: list[ProgramSource], step_limit: int, seed: int) -> dict[int, list[str]]:
    """Per report row: the changed lines of each given program against the generated one and what they change in
    its first nominal runs (cycle time, waits, messages, outputs, move settings, moves, the stop). Rows whose
    programs are as generated have none. A difference is reported whether or not verify judges it a mismatch."""
    out: dict[int, list[str]] = {}
    for source in sources:
        if source.model is not None:
            continue
        twin = _twin(cell, source)
        if twin is None:
            continue
        changed = _changed_lines(source, twin)
        if not changed:
            continue
        texts = [
            f"EDIT effect: shows {new!r} where the generated program shows {old!r} (a text changed: the same message, "
            "the same stop)"
            for old, new in _texts(source, twin).items()
        ]
        out.setdefault(source.row, []).extend(changed + texts + _effects(cell, source, twin, step_limit, seed))
    return out


# A string literal as the programs verify reads write their texts: "..." ("" inside: a quote in one language; \
# escapes). A quote mark in a comment (the arm's) is no literal: the texts are double-quoted.
LITERAL = re.compile(r'"(?:[^"\\]|\\.|"")*"')


def message_renames(cell, source: ProgramSource) -> dict[str, str]:
    """The texts a given program changes and nothing else on their lines (a message translated): generated text ->
    given text. A stop whose message is the generated one's with these texts replaced is the same stop, at the same
    place for the same cause: an edit, not a mismatch. {} for a generated program."""
    if source.model is not None or source.origin[0].startswith("<fresh>"):
        return {}
    twin = _twin(cell, source)
    return {} if twin is None else _texts(source, twin)


def _texts(source: ProgramSource, twin: ProgramSource) -> dict[str, str]:
    """Texts changed alone on their lines; a text changed into another the generated program has (another stop's
    message: the stop's cause no longer told by it) is not a rename."""
    out: dict[str, str] = {}
    generated = {text[1:-1] for f in twin.files for text in LITERAL.findall(f.text)}
    for mine, theirs in _pairs(source, twin):
        a, b = theirs.text.splitlines(), mine.text.splitlines()
        for op, a0, a1, b0, b1 in difflib.SequenceMatcher(None, a, b, autojunk=False).get_opcodes():
            if op != "replace":
                continue
            for old_line, new_line in zip(a[a0:a1], b[b0:b1], strict=False):
                olds, news = LITERAL.findall(old_line), LITERAL.findall(new_line)
                if len(olds) != len(news) or LITERAL.sub('""', old_line) != LITERAL.sub('""', new_line):
                    continue  # more than a text changed on the line: not a translation
                out.update(
                    (o[1:-1], n[1:-1])
                    for o, n in zip(olds, news, strict=True)
                    if o != n and o[1:-1] and n[1:-1] not in generated
                )
    return out



def _twin(cell, source: ProgramSource) -> ProgramSource | None:
    for fresh in fresh_sources(cell, [source.target], only={source.kind}):
        if fresh.index == source.index:
            return fresh
    return None


def _pairs(source: ProgramSource, twin: ProgramSource):
    """(given file, generated file) of one program: the program files, then each other file with the generated one
    of its name (pal.dat with pal.dat, pal_count.dat with pal_count.dat: never crossed by their suffix); a
    program file renamed renames its data files alike (mine.dat, mine_count.dat); a suffix pairs alone only where
    one file of each side has it."""
    mine_main, their_main = source.files[0], twin.files[0]
    yield mine_main, their_main
    mine_stem, their_stem = Path(mine_main.name).stem.lower(), Path(their_main.name).stem.lower()
    theirs = {Path(f.name).name.lower(): f for f in twin.files[1:]}
    left = []
    for mine in source.files[1:]:
        name = Path(mine.name).name.lower()
        renamed = their_stem + name[len(mine_stem) :] if name.startswith(mine_stem) else None
        other = theirs.pop(name, None) or (theirs.pop(renamed, None) if renamed else None)
        if other is not None:
            yield mine, other
        else:
            left.append(mine)
    for mine in left:
        suffix = Path(mine.name).suffix.lower()
        alike = [n for n, f in theirs.items() if Path(n).suffix == suffix]
        if len(alike) == 1 and sum(Path(f.name).suffix.lower() == suffix for f in left) == 1:
            yield mine, theirs.pop(alike[0])


def _changed_lines(source: ProgramSource, twin: ProgramSource) -> list[str]:
    """`file:line` and the text of each line added, removed or changed against the generated program."""
    out: list[str] = []
    for mine, theirs in _pairs(source, twin):
        a, b = theirs.text.splitlines(), mine.text.splitlines()
        name = Path(mine.name).name
        for op, a0, a1, b0, b1 in difflib.SequenceMatcher(None, a, b, autojunk=False).get_opcodes():
            if op == "equal":
                continue
            for i in range(b0, b1):
                out.append(f"{name}:{i + 1} {'changed' if op == 'replace' else 'added'}: {b[i].strip()}")
            if op == "delete" or (op == "replace" and a1 - a0 > b1 - b0):
                gone = a[a0 + (b1 - b0) if op == "replace" else a0 : a1]
                out.extend(f"{name}: removed after line {b0}: {text.strip()}" for text in gone)
    if len(out) > SHOWN_LINES:
        out = [*out[:SHOWN_LINES], f"... and {len(out) - SHOWN_LINES} more changed lines"]
    return [f"EDIT {line}" for line in out]


def _effects(cell, source: ProgramSource, twin: ProgramSource, step_limit: int, seed: int) -> list[str]:
    """What the changes do in the first nominal runs, as differences of the two traces (each said once)."""
    kind = cell.kinds[source.kind].verify
    cases = [c for c in kind.cases(cell, source, 1, seed) if c.start == "home" and c.scenario not in SCENARIOS]
    cases = [c for c in cases if c.category == cases[0].category][:EDIT_CASES] if cases else []
    arm = Checker(cell, source.target).arm
    try:
        programs = (source.load(), twin.load())
    except RunError as exc:
        return [f"EDIT effect not known: {exc}"]
    seen: dict[str, None] = {}
    for case in cases:
        traces = []
        for program in programs:
            setup = kind.setup(cell, source, case)
            try:
                traces.append(program.run(setup.inputs, **setup.run_options(arm, step_limit)))
            except RunError as exc:
                traces.append(exc)
        for text in _differences(*traces, setting_names(source.target)):
            seen.setdefault(f"EDIT effect: {text}", None)
    return list(seen) or ["EDIT effect: none in the nominal runs (moves, outputs, messages, settings, time alike)"]


def _differences(mine: Trace | RunError, theirs: Trace | RunError, names: dict[str, str]) -> list[str]:
    if isinstance(mine, RunError) or isinstance(theirs, RunError):
        if isinstance(mine, RunError) and not isinstance(theirs, RunError):
            return [f"the run stops with an error where the generated program's does not: {mine}"]
        return []
    out = []
    if mine.halted != theirs.halted or (mine.halted and mine.halt_message != theirs.halt_message):
        said = f"stops ({halt_text(mine)!r})" if mine.halted else "does not stop"
        out.append(f"the program {said} where the generated program {_stop_of(theirs)}")
    if len(mine.moves) != len(theirs.moves):
        out.append(f"{len(mine.moves)} moves where the generated program makes {len(theirs.moves)}")
    out += _poses(mine, theirs) + _settings(mine, theirs, names) + _timing(mine, theirs)
    extra = Counter(mine.messages) - Counter(theirs.messages)
    missing = Counter(theirs.messages) - Counter(mine.messages)
    out += [f"writes {m!r} (the generated program does not)" for m in extra]
    out += [f"does not write {m!r}" for m in missing]
    out += _outputs(mine, theirs)
    return out


def _stop_of(trace: Trace) -> str:
    return f"stops ({halt_text(trace)!r})" if trace.halted else "does not"


def _settings(mine: Trace, theirs: Trace, names: dict[str, str]) -> list[str]:
    """Move settings the given program has and the generated one has not (or other values): each difference
    once, with the moves it holds on (from the first move's line)."""
    spans: dict[tuple, list[int]] = {}
    for i, (m, t) in enumerate(zip(mine.moves, theirs.moves, strict=False)):
        for key in sorted(set(m.settings) | set(t.settings)):
            have, want = _plain(m.settings.get(key)), _plain(t.settings.get(key))
            if have != want:
                spans.setdefault((key, _shown(have), _shown(want)), []).append(i)
    out = []
    for (key, have, want), moves in spans.items():
        first, last = moves[0], moves[-1]
        which = f"move {first + 1}" if first == last else f"moves {first + 1}-{last + 1}"
        out.append(f"{which} (from line {mine.moves[first].line}) {names.get(key, key)} {have}, generated {want}")
    return out


def _poses(mine: Trace, theirs: Trace) -> list[str]:
    """Moves whose target the given program moved (beyond float32's 0.005 mm, 0.001 deg: verify's pose tolerance):
    each distinct offset once, with the moves it holds on (from the first move's line)."""
    pos_tol, rot_tol = TOLERANCES["float32"]
    spans: dict[tuple, list[int]] = {}
    for i, (m, t) in enumerate(zip(mine.moves, theirs.moves, strict=False)):
        if m.tcp2base is None or t.tcp2base is None:
            continue
        offset = np.asarray(m.tcp2base)[:3, 3] - np.asarray(t.tcp2base)[:3, 3]
        turn = np.asarray(t.tcp2base)[:3, :3].T @ np.asarray(m.tcp2base)[:3, :3]
        angle = math.degrees(math.acos(max(-1.0, min(1.0, (float(np.trace(turn)) - 1.0) / 2.0))))
        distance = float(np.linalg.norm(offset))  # its length, the same whatever the reading turns
        if distance > pos_tol or angle > rot_tol:
            spans.setdefault((format_literal(distance, 3), format_literal(angle, 3)), []).append(i)
    out = []
    for (distance, angle), moves in spans.items():
        first, last = moves[0], moves[-1]
        which = f"move {first + 1}" if first == last else f"moves {first + 1}-{last + 1}"
        out.append(
            f"{which} (from line {mine.moves[first].line}) {distance} mm and {angle} deg from the generated "
            "program's target"
        )
    return out


def _plain(value):
    if isinstance(value, dict):
        return {k: v for k, v in value.items() if k != "line"}  # where a setting was written is the diff's
    return value


def _shown(value) -> str:
    if value is None:
        return "not set"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} {_shown(v)}" for k, v in value.items()) + "}"
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def _timing(mine: Trace, theirs: Trace) -> list[str]:
    """Where the given program's clock departs from the generated one's: before the first move whose arrival
    differs (a wait, a slower move), and the whole run's time."""
    out = []
    for i, (m, t) in enumerate(zip(mine.moves, theirs.moves, strict=False)):
        delta = m.end_time - t.end_time
        if abs(delta) > TIME_STEP_S:
            out.append(f"reaches move {i + 1} (line {m.line}) {_seconds(delta, 'later', 'earlier')}")
            break
    total = mine.clock - theirs.clock
    if abs(total) > TIME_STEP_S and math.isfinite(total):
        out.append(
            f"the run takes {_seconds(total, 'longer', 'less')} ({mine.clock:.2f} s, generated {theirs.clock:.2f} s)"
        )
    return out


def _seconds(delta: float, more: str, less: str) -> str:
    amount = f"{abs(delta):.2f}" if abs(delta) >= 0.005 else f"{abs(delta):.2g}"
    return f"{amount} s {more if delta > 0 else less} than the generated program"


def _outputs(mine: Trace, theirs: Trace) -> list[str]:
    def key(e):
        return (e.name, e.value, e.after_moves)

    have, want = Counter(map(key, mine.outputs)), Counter(map(key, theirs.outputs))
    lines = {key(e): e.line for e in mine.outputs}
    out = [
        f"sets {n} {v} after move {k} (line {lines[(n, v, k)]}); the generated program does not"
        for n, v, k in have - want
    ]
    out += [f"does not set {n} {v} after move {k} as the generated program does" for n, v, k in want - have]
    return out
