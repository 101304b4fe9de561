"""Every `codegen ...` command in a shell block of README.md and docs/ is parsed by the real command line (a renamed
or removed option fails here), and the cheap ones run for real in a copy of the examples."""

from __future__ import annotations

import re
import shlex
import shutil
from dataclasses import dataclass
from pathlib import Path

import click
import pytest
from click.testing import CliRunner

from codegen.cli import main

REPO = Path(__file__).resolve().parents[2]
PAGES = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
SHELL = {"sh", "bash", "shell", "console"}  # the blocks whose lines are commands
SEPARATORS = {"&&", "||", ";", "|", "&", "(", ")"}
KEYWORDS = {"do", "then", "else", "time", "!"}  # a shell word before a command
# run for real unless expensive: verify over whole cells (parsed only), the derivation's proofs (sympy)
PARSE_ONLY = {"verify", "derive"}
FENCE = re.compile(r"^(?P<indent>\s*)(?P<fence>`{3,}|~{3,})(?P<info>[^`\n]*)$")


@dataclass(frozen=True)
class Command:
    page: str
    line: int
    args: tuple[str, ...]

    def __str__(self) -> str:
        return f"{self.page}:{self.line}: codegen {shlex.join(self.args)}"


def blocks(text: str):
    """(info, first line number, lines) of every fenced code block, indented ones (in a list) too."""
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        match = FENCE.match(lines[i])
        if not match:
            i += 1
            continue
        fence, indent = match["fence"], len(match["indent"])
        body, start = [], i + 2
        i += 1
        while i < len(lines) and not re.match(rf"^\s*{re.escape(fence)}\s*$", lines[i]):
            body.append(lines[i][indent:] if lines[i][:indent].isspace() else lines[i].lstrip())
            i += 1
        yield match["info"].strip().split(" ")[0].lower(), start, body
        i += 1


def words(line: str) -> list[str]:
    lexer = shlex.shlex(line, posix=True, punctuation_chars=True)
    lexer.whitespace_split = True
    lexer.commenters = "#"
    return list(lexer)


def codegen_args(segment: list[str]) -> tuple[str, ...] | None:
    """The arguments of a shell segment that runs codegen (`codegen`, `.venv/bin/codegen`, `python -m codegen`)."""
    while segment and (segment[0] in KEYWORDS or re.fullmatch(r"[A-Za-z_]\w*=.*", segment[0])):
        segment = segment[1:]
    if not segment:
        return None
    if Path(segment[0]).name == "codegen":
        return tuple(segment[1:])
    if re.fullmatch(r"python3?(\.\d+)?", Path(segment[0]).name) and segment[1:3] == ["-m", "codegen"]:
        return tuple(segment[3:])
    return None


def commands(page: Path) -> list[Command]:
    out = []
    for info, start, body in blocks(page.read_text(encoding="utf-8")):
        joined: list[tuple[int, str]] = []
        for n, line in enumerate(body, start=start):
            if joined and joined[-1][1].endswith("\\"):
                joined[-1] = (joined[-1][0], joined[-1][1][:-1] + " " + line.strip())
            else:
                joined.append((n, line.strip().removeprefix("$ ")))
        for n, line in joined:
            if info not in SHELL:
                continue
            segment: list[str] = []
            for word in [*words(line), ";"]:
                if word in SEPARATORS:
                    args = codegen_args(segment)
                    if args is not None:
                        out.append(Command(str(page.relative_to(REPO)), n, args))
                    segment = []
                else:
                    segment.append(word)
    return out


ALL = [c for page in PAGES for c in commands(page)]
HIDDEN = re.compile(r"^\s*(\$ |\S*/)codegen\s|^\s*\S*python3? -m codegen\s")  # a command line, not output


def test_commands_stand_in_shell_blocks():
    """A command shown in a block of another language (text, toml) would escape these tests."""
    hidden = [
        f"{page.name}:{start + k}: {line}"
        for page in PAGES
        for info, start, body in blocks(page.read_text(encoding="utf-8"))
        if info not in SHELL
        for k, line in enumerate(body)
        if HIDDEN.match(line)
    ]
    assert not hidden, hidden


def parse(args: tuple[str, ...]) -> tuple[str, ...]:
    """The command's path (e.g. ('calibrate', 'tcp')) after click parsed every option and argument of it."""
    ctx = main.make_context("codegen", list(args))
    command: click.Command = main
    path: list[str] = []
    while isinstance(command, click.Group):
        rest = [*getattr(ctx, "_protected_args", []), *ctx.args]
        name, sub, rest = command.resolve_command(ctx, rest)
        assert sub is not None, f"no command {rest[:1]}"
        path.append(name)
        ctx = sub.make_context(name, rest, parent=ctx)
        command = sub
    return tuple(path)


def leaf_commands(group: click.Group, prefix: tuple[str, ...] = ()) -> set[tuple[str, ...]]:
    out = set()
    for name, command in group.commands.items():
        if isinstance(command, click.Group):
            out |= leaf_commands(command, (*prefix, name))
        else:
            out.add((*prefix, name))
    return out


def test_the_pages_show_commands_and_every_command_has_an_example(monkeypatch):
    monkeypatch.chdir(REPO)  # the examples' paths are the repository's
    assert len(ALL) >= 30, [str(c) for c in ALL]
    shown = {parse(c.args) for c in ALL}
    assert leaf_commands(main) <= shown, f"commands without an example: {sorted(leaf_commands(main) - shown)}"


@pytest.mark.parametrize("command", ALL, ids=str)
def test_each_command_parses(command, monkeypatch):
    monkeypatch.chdir(REPO)
    try:
        parse(command.args)
    except click.ClickException as exc:
        pytest.fail(f"{command}: {exc.format_message()}")


def test_the_cheap_commands_run(tmp_path, monkeypatch):
    """Each page's commands in order, in a copy of the examples, their generated programs and the pages (so
    --write, generate and schema --out change the copy): each must exit 0. Repeated commands run once."""
    seen: set[tuple[str, ...]] = set()
    runner = CliRunner()
    failures = []
    for page in PAGES:
        folder = tmp_path / page.stem
        shutil.copytree(REPO / "codegen" / "examples", folder / "codegen" / "examples")
        shutil.copytree(REPO / "generated", folder / "generated", ignore=shutil.ignore_patterns(".*"))
        shutil.copytree(REPO / "docs", folder / "docs")  # the reference page codegen schema writes
        monkeypatch.chdir(folder)
        for command in commands(page):
            shell = any("$" in a or "*" in a for a in command.args)
            if shell or parse(command.args)[0] in PARSE_ONLY or command.args in seen:
                continue
            seen.add(command.args)
            result = runner.invoke(main, list(command.args))
            if result.exit_code != 0:
                failures.append(f"{command}: exit {result.exit_code}\n{result.output[-800:]}{result.exception!r}")
    assert not failures, "\n".join(failures)
    assert len(seen) >= 20


def test_the_readme_quick_start_is_what_ci_runs():
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    quick = readme.split("## Quick start", 1)[1]
    _, _, lines = next(blocks(quick))
    ci = (REPO / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    assert len(lines) == 2
    for line in lines:
        assert line in ci, f"the README's quick start line is not in .ci/run verbatim: {line}"


def test_the_install_and_docs_commands_a_new_user_copies_run_from_the_venv():
    """The README's docs command read `pip install '.[docs]' && mkdocs serve`: on a fresh machine outside the venv."""
    bare = re.compile(r"(?<![\w/.-])(pip install|mkdocs serve)\b")
    found = [
        f"{page.name}: {match.group()}"
        for page in (REPO / "README.md", REPO / "docs" / "getting-started.md")
        for match in bare.finditer(page.read_text(encoding="utf-8"))
    ]
    assert not found, found
