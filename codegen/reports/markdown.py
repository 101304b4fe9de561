"""`codegen diff --format markdown`: per changed cell and program what the change does, short enough for a
pull-request comment: a summary table, the details, the raw diff folded."""

from __future__ import annotations

from codegen.reports.program_diff import CellChange, ProgramChange

SHOWN = 8  # items of a group listed (the rest counted)
RAW_LINES = 400  # lines of the raw diff folded in (the rest counted): a comment has a size limit


def markdown(changes: list[CellChange]) -> str:
    """Every cell's change; a cell without one is named as unchanged in the summary line."""
    changed = [c for c in changes if c.programs]
    out = [f"### codegen diff: {len(changed)} of {len(changes)} cell{'s' if len(changes) != 1 else ''} changed", ""]
    for change in changes:
        if not change.programs:
            out.append(f"- `{change.cell}`: programs as generated" + _verdict_text(change))
    if len(out) > 2:
        out.append("")
    for change in changed:
        out += _cell(change)
    return "\n".join(out).rstrip() + "\n"


def _verdict_text(change: CellChange) -> str:
    return f"; verify: {change.verify}" if change.verify else ""


def _cell(change: CellChange) -> list[str]:
    out = [f"#### `{change.cell}`" + (f" ({change.cell_file})" if change.cell_file else ""), ""]
    if change.verify:
        out += [f"verify of the new programs: {change.verify}", ""]
    out += [
        "| target | program | change | stations | poses moved | largest move | settings | I/O | messages | stops "
        "| verify |",
        "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |",
    ]
    for p in change.programs:
        mm, deg = p.largest_move
        largest = f"{mm:.3f} mm, {deg:.3f} deg" if p.moved else ""
        counts = [len(p.stations), len(p.moved), largest, len(p.settings), len(p.io), len(p.messages), len(p.stops)]
        shown = " | ".join(str(c) if c != 0 else "" for c in counts)
        out.append(f"| {p.target} | `{p.program}` | {p.status} | {shown} | {_verdict(p)} |")
    out.append("")
    for p in change.programs:
        out += _details(p)
    return out


def _verdict(p: ProgramChange) -> str:
    if p.verdict is None:
        return ""
    return ("pass: " if p.passed else "**FAIL**: ") + p.verdict


def _details(p: ProgramChange) -> list[str]:
    files = f"; files changed: {', '.join(f'`{name}`' for name in p.changed_files)}" if p.changed_files else ""
    out = [f"##### {p.target}: `{p.program}` ({p.status}, {p.changed_lines} changed lines{files})", ""]
    for name, title in ProgramChange.GROUPS:
        items = getattr(p, name)
        if not items:
            continue
        out.append(f"- {title}:")
        out += [f"  - {_inline(item)}" for item in items[:SHOWN]]
        if len(items) > SHOWN:
            out.append(f"  - ... and {len(items) - SHOWN} more")
    if p.raw:
        lines = p.raw.splitlines()
        body = lines[:RAW_LINES] + ([f"... and {len(lines) - RAW_LINES} more lines"] if len(lines) > RAW_LINES else [])
        fence = "`" * max(3, 1 + max((_run(line) for line in body), default=0))  # longer than any run inside
        out += [
            "",
            f"<details><summary>raw diff ({len(lines)} lines)</summary>",
            "",
            fence + "diff",
            *body,
            fence,
            "",
            "</details>",
        ]
    out.append("")
    return out


def _inline(text: str) -> str:
    """A sentence of the report as inline text (program text in it stays text: no markup, no HTML)."""
    return text.replace("\\", "\\\\").replace("<", "&lt;").replace("|", "\\|").replace("`", "\\`").replace("*", "\\*")


def _run(line: str) -> int:
    """The longest run of backticks in a line."""
    longest = count = 0
    for c in line:
        count = count + 1 if c == "`" else 0
        longest = max(longest, count)
    return longest
