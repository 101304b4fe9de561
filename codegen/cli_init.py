"""`codegen init`: write a commented starter cell file of a program kind, for the targets asked."""

from __future__ import annotations

from pathlib import Path

import click

from codegen.cli_base import UserError, main


@main.command()
@click.argument("kind")  # a program kind, or a mode of one (station: point, frame)
@click.option("--target", "targets", multiple=True, help="Only this target (repeatable); default: the starter's.")
@click.option("--out", "out", default=None, type=click.Path(dir_okay=False), help="The file (default: <cell>.toml).")
def init(kind: str, targets: tuple[str, ...], out: str | None) -> None:
    """Write a starter cell file of KIND (a program kind or one of its modes: its tables, commented values that
    generate and verify as written) to edit into one's own cell; an existing file is never replaced."""
    import tomllib

    from codegen.controllers import target_names
    from codegen.protocol import installed_kinds
    from codegen.starter import StarterError, example_of, starter_text

    starters = {name: (k, trim) for k in installed_kinds().values() for name, trim in k.section.starters().items()}
    if kind not in starters:
        raise UserError(f"{kind}: not a program kind (the kinds: {', '.join(starters)})")
    owner, trim = starters[kind]
    try:
        text = starter_text(example_of(owner.section.tables), targets, tuple(target_names()), trim)
    except StarterError as exc:
        raise UserError(f"init {kind}: {exc}") from None
    path = Path(out) if out is not None else Path(f"{tomllib.loads(text)['cell']['name']}.toml")
    try:
        with path.open("x", encoding="utf-8") as f:  # "x": a file already there stays as it is
            f.write(text)
    except FileExistsError:
        raise UserError(f"{path}: the file exists; give another --out (an existing file is never replaced)") from None
    except OSError as exc:
        raise UserError(f"{path}: cannot write: {exc.strerror}") from None
    click.echo(f"wrote {path}: a {kind} cell for {', '.join(tomllib.loads(text)['cell']['targets'])}")
