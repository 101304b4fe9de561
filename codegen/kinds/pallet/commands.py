"""`codegen pallet`: the boxes of every pallet of a cell, its checks, a cycle estimate, and pictures of every layer."""

from __future__ import annotations

from pathlib import Path

import click

from codegen import protocol
from codegen.cli_base import Folder, UserError
from codegen.cli_base import dump as _dump
from codegen.kinds.pallet.pictures import MARKS, pictures
from codegen.kinds.pallet.report import load_pallet_file, report, text
from codegen.kinds.pallet.shape import pallet_shape
from codegen.model.cell import EXAMPLES_DIR, CellError
from codegen.writefile import WriteRefused, check_own, write_own

TESTMAT = EXAMPLES_DIR / "pallets" / "testmat_pallet.toml"


@click.command("pallet")
@click.argument("cell", required=False, type=click.Path(dir_okay=False))
@click.option("--json", "as_json", is_flag=True, help="JSON (keys in docs/kinds/pallet.md) instead of text.")
@click.option("--svg", "svg_dir", type=Folder(), help="Write one SVG per layer into this folder.")
def pallet(cell, as_json, svg_dir) -> None:
    """Every box of every [[pallet]] of CELL (default: source 004's test pallet) with its target, entry,
    approach and retreat in the pallet and the base frame; overlapping or overhanging boxes are refused."""

    try:
        data = load_pallet_file(cell or TESTMAT)
    except CellError as exc:
        raise UserError(str(exc)) from None
    if not data.pallets:
        raise UserError(f"{data.source}: no [[pallet]] table")
    for warning in data.warnings:
        click.echo(f"warning: {warning}", err=True)
    result = report(data)
    if svg_dir is not None:
        folder = Path(svg_dir)
        drawn = {name: svg for p in data.pallets for name, svg in pictures(pallet_shape(data.cell, p)).items()}
        try:
            for name in drawn:  # every picture's place checked before the first is written
                check_own(folder / name, MARKS)
            for name, svg in drawn.items():
                write_own(folder / name, svg, MARKS)  # whole; a symlink's target replaced, kept a link
        except WriteRefused as exc:
            raise UserError(f"{folder}: cannot write the pictures: {exc}") from None
        except OSError as exc:
            raise UserError(f"{folder}: cannot write the pictures: {exc.strerror or exc}") from None
    if as_json:
        _dump(result)
    else:
        click.echo(text(result))


class CommandsPart(protocol.Commands):
    def commands(self) -> list:
        return [(None, pallet)]
