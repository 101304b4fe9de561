"""The command line's group, its bad-input error and the helpers every command module shares."""

from __future__ import annotations

import errno
import json
import math

import click

from codegen.controllers import all_targets, target_names
from codegen.csvfile import number, whole
from codegen.model.cell import CellError, load_cell
from codegen.terminal import inert_output

EXIT_BAD_INPUT = 2
MAX_STEP_LIMIT = 100_000_000  # interpreter steps: some 7 minutes of a busy loop (250,000 steps/s measured)
# a folder the user gave that cannot take the output (no permission, read-only, a file on the way): exit 2
FOLDER_REFUSED = frozenset({errno.EACCES, errno.EPERM, errno.EROFS, errno.ENOTDIR, errno.EEXIST, errno.EISDIR})


class UserError(click.ClickException):
    """A bad input: message to stderr, exit 2, no traceback."""

    exit_code = EXIT_BAD_INPUT


class Number(click.ParamType):
    """A finite number written in decimal digits (no nan, inf or 1_000: the calibration files' syntax) within
    [low, high] (`above`: strictly above low); `integer`: a whole number; `count` > 1: that many, comma-separated,
    as a tuple. Every numeric option of every command takes one, so each says its range in its error."""

    name = "number"

    def __init__(self, low=None, high=None, *, above=False, integer=False, count=1):
        self.low, self.high, self.above, self.integer, self.count = low, high, above, integer, count

    def convert(self, value, param, ctx):
        if self.count == 1 and isinstance(value, int | float) and not isinstance(value, bool):
            return self._checked(value)  # a default
        if self.count > 1 and isinstance(value, tuple):
            return value
        parts = str(value).split(",") if self.count > 1 else [str(value)]
        if len(parts) != self.count:
            self.fail(f"expected {self.count} comma-separated {self._what()}s, got {value!r}", param, ctx)
        values = []
        for part in parts:
            try:
                values.append(whole(part) if self.integer else number(part))
            except ValueError:
                self.fail(f"{part.strip()!r} is not a {self._what()} (decimal digits; no nan or inf)", param, ctx)
            if not self._within(values[-1]):
                self.fail(f"{part.strip()} is not {self._range()}", param, ctx)
        return tuple(values) if self.count > 1 else values[0]

    def _checked(self, value):
        if not self._within(value):
            self.fail(f"{value} is not {self._range()}")
        return value

    def _within(self, value) -> bool:
        if isinstance(value, float) and not math.isfinite(value):
            return False
        if self.low is not None and (value <= self.low if self.above else value < self.low):
            return False
        return self.high is None or value <= self.high

    def _what(self) -> str:
        return "whole number" if self.integer else "number"

    def _range(self) -> str:
        low, high = _shown(self.low), _shown(self.high)
        if low and high and not self.above:
            return f"within {low} .. {high}"
        parts = [f"above {low}" if self.above else f"at least {low}"] if low else []
        if high:
            parts.append(f"at most {high}")
        return " and ".join(parts) or "finite"

    def get_metavar(self, param, ctx=None) -> str:
        return ",".join(["INTEGER" if self.integer else "NUMBER"] * self.count)


def _shown(bound) -> str:
    return "" if bound is None else f"{bound:,}" if isinstance(bound, int) else f"{bound:,g}"


class Folder(click.Path):
    """A folder to write into: never the empty path (which would be the current folder, unasked)."""

    def __init__(self):
        super().__init__(file_okay=False)

    def convert(self, value, param, ctx):
        if isinstance(value, str) and not value.strip():
            self.fail("an empty path; give a folder", param, ctx)
        return super().convert(value, param, ctx)


def load(cell_path):
    try:
        cell = load_cell(cell_path)
    except CellError as exc:
        raise UserError(str(exc)) from None
    for warning in cell.warnings:
        click.echo(f"warning: {warning}", err=True)
    return cell


def write_cell(model, targets: list[str] | None, out_dir):
    """`codegen generate` of one loaded cell (codegen.generate.generate): its written paths, what was left alone
    and the margins; UserError (exit 2) for what the user can fix, ClickException for a busy or failing folder."""
    from codegen.emit import EmitError
    from codegen.generate import GenerateError, generate
    from codegen.output import OutputBusy, OutputInTheWay

    try:
        return generate(model, targets, out_dir)
    except (EmitError, GenerateError) as exc:
        raise UserError(f"{model.source}: {exc}") from None
    except OutputBusy as exc:
        raise click.ClickException(str(exc)) from None
    except OutputInTheWay as exc:
        raise UserError(str(exc)) from None
    except OSError as exc:
        error = UserError if exc.errno in FOLDER_REFUSED else click.ClickException  # the user's to fix: exit 2
        where = exc.filename or out_dir
        raise error(f"{where}: cannot write ({exc.strerror or exc}); previous output left as it was") from None


def diff_cell(model, out_dir) -> str:
    """`codegen diff` of one loaded cell: the unified diff against out_dir ('' when identical)."""
    from codegen.emit import EmitError
    from codegen.generate import diff

    try:
        return diff(model, out_dir)
    except EmitError as exc:
        raise UserError(f"{model.source}: {exc}") from None


def format_option():
    """--format of the commands that report findings: their text or JSON, or a format a CI system reads."""
    from codegen.reports.formats import FORMATS

    return click.option(
        "--format",
        "report_format",
        type=click.Choice(FORMATS),
        default="text",
        show_default=True,
        help="text, json (as --json), junit (JUnit XML), sarif (SARIF 2.1.0) or github (workflow annotations).",
    )


def chosen_format(report_format: str, as_json: bool) -> str:
    """The format asked for: --json is --format json; with another --format it is a contradiction (exit 2)."""
    if as_json and report_format not in ("text", "json"):
        raise UserError(f"--json and --format {report_format}: choose one")
    return "json" if as_json else report_format


def step_limit_option(help_text: str, kinds_own: bool = False):
    """--step-limit of the commands that run programs: the interpreter's default, or (kinds_own) none, so that
    each kind's runs keep their own limit unless one is given."""
    from codegen.dialects.core.machine import DEFAULT_STEP_LIMIT

    default = None if kinds_own else DEFAULT_STEP_LIMIT
    return click.option(
        "--step-limit",
        default=default,
        show_default=not kinds_own,
        type=Number(1, MAX_STEP_LIMIT, integer=True),
        help=help_text,
    )


def file_target_option():
    """--target of the commands that take program files: the controller, else the one each file's suffix names."""
    return click.option(
        "--target",
        "target_name",
        type=click.Choice(target_names()),
        help="Controller (default: from the file suffixes): "
        + "; ".join(f"{t.name} = {t.title}" for t in all_targets())
        + ".",
    )


def dump(data) -> None:
    click.echo(json.dumps(data, indent=2, sort_keys=False))


class InertGroup(click.Group):
    """The command group whose every word printed, its messages and click's own errors, goes through
    codegen.terminal.inert: nothing from a cell, a program or an argument changes what the terminal does."""

    def main(self, *args, **kwargs):
        with inert_output():
            return super().main(*args, **kwargs)


@click.group(cls=InertGroup, context_settings={"color": True})  # click strips nothing: all is shown escaped
@click.version_option(package_name="codegen")
def main() -> None:
    """Vision-corrected robot programs: derive, correct, generate, run, verify."""


@main.group()
def calibrate() -> None:
    """Calibration computations (each kind's: camera, tool, belt)."""
