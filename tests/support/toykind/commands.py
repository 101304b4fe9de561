"""The toy kind's command: `codegen toy-greeting CELL` prints the cell's greeting."""

from __future__ import annotations

import click

from codegen import protocol


@click.command("toy-greeting")
@click.argument("cell_path", type=click.Path(dir_okay=False))
def toy_greeting(cell_path: str) -> None:
    """Print the toy cell's greeting."""
    from codegen.model.cell import load_cell

    cell = load_cell(cell_path)
    click.echo(cell.sections["toy"].greeting)


class ToyCommands(protocol.Commands):
    def commands(self) -> list:
        return [(None, toy_greeting)]
