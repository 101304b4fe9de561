"""Command line: thin wrappers that parse options, call one function and print (`codegen` is `main`)."""

from __future__ import annotations

import sys

import click

from codegen import cli_calibrate, cli_check, cli_pallet, cli_run  # noqa: F401  (they register their commands)
from codegen.cli_base import UserError, main, step_limit_option
from codegen.cli_base import dump as _dump
from codegen.cli_base import load as _load
from codegen.controllers import target_names


@main.command()
@click.option("--check", is_flag=True, help="Prove every identity; exit 1 unless each has its expected status.")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def derive(check: bool, as_json: bool) -> None:
    """Print the derivation of the correction transform (and prove its identities)."""
    from codegen import derivation  # sympy: only this command imports it

    d = derivation.derive()
    result = {"description": derivation.describe(d)}
    ok = True
    if check:
        ids = derivation.identities(d)
        ok = all(i.as_expected for i in ids)
        result["identities"] = [
            {
                "name": i.name,
                "statement": i.statement,
                "expected": i.expected,
                "status": i.status,
                "as_expected": i.as_expected,
                "detail": i.detail,
            }
            for i in ids
        ]
        result["ok"] = ok
    if as_json:
        _dump(result)
    else:
        click.echo(result["description"])
        if check:
            click.echo("")
            click.echo(f"{'identity':<34}{'expected':<10}{'status':<10}ok")
            for i in result["identities"]:
                click.echo(f"{i['name']:<34}{i['expected']:<10}{i['status']:<10}{'yes' if i['as_expected'] else 'NO'}")
                click.echo(f"    {i['statement']}")
                click.echo(f"    {i['detail']}")
            click.echo("all identities as expected" if ok else "SOME IDENTITIES NOT AS EXPECTED")
    sys.exit(0 if ok else 1)


def _parse_mark(value: str) -> tuple[float, float, float]:
    parts = value.split(",")
    if len(parts) != 3:
        raise UserError(f"--mark: expected X,Y,THETA (3 numbers), got {len(parts)} in {value!r}")
    try:
        return tuple(float(p) for p in parts)  # NaN and inf are allowed: the guard must catch them
    except ValueError:
        raise UserError(f"--mark: not numbers: {value!r}") from None


@main.command()
@click.argument("cell", required=False, type=click.Path(dir_okay=False))
@click.option("--station", "station_id", required=True, type=int, help="Station id read by the camera.")
@click.option("--mark", required=True, help="Mark now: X,Y,THETA (base frame, mm, deg, as the camera reports).")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def correct(cell: str | None, station_id: int, mark: str, as_json: bool) -> None:
    """Reference result for one reading: guard outcome and every corrected pose."""
    from codegen.correct import correct_report, format_report
    from codegen.kinds.point import PointKind, Reading

    model = _load(cell)
    x, y, theta = _parse_mark(mark)
    station = model.station_by_id(station_id)
    if station is not None and station.kind != PointKind.name:
        raise UserError(
            f"{model.source}: station {station_id} ({station.name}) is a {station.kind} station: only point "
            "stations are corrected from one reading (see `codegen verify` for the others)"
        )
    report = correct_report(model, Reading(station_id, x, y, theta))
    if as_json:
        _dump(report)
    else:
        click.echo(format_report(report))


@main.command()
@click.argument("cell", required=False, type=click.Path(dir_okay=False))
@click.option("--target", "targets", multiple=True, help="Only this target (repeatable); default: the cell's targets.")
@click.option("--out", "out_dir", default="generated", show_default=True, type=click.Path(file_okay=False))
@click.option("--json", "as_json", is_flag=True, help="Report written files and the arm's margins as JSON.")
def generate(cell: str | None, targets: tuple[str, ...], out_dir: str, as_json: bool) -> None:
    """Write the programs of every target under OUT/<cell>/<target>/ (all or nothing)."""
    from pathlib import Path

    from codegen.emit import EmitError
    from codegen.generate import GenerateError
    from codegen.generate import generate as run_generate
    from codegen.output import OutputBusy

    model = _load(cell)
    for t in targets:
        if t not in model.targets:
            raise UserError(f"--target {t}: not a target of cell {model.name} ({', '.join(model.targets)})")
    try:
        written, left_alone, envelopes = run_generate(model, list(targets) or None, Path(out_dir))
    except (EmitError, GenerateError) as exc:
        raise UserError(f"{model.source}: {exc}") from None
    except OutputBusy as exc:
        raise click.ClickException(str(exc)) from None
    except OSError as exc:
        raise click.ClickException(
            f"{out_dir}: cannot write ({exc.strerror or exc}); previous output left as it was"
        ) from None

    if as_json:
        _dump(
            {
                "cell": model.name,
                "written": [str(p) for p in written],
                "left_alone": left_alone,
                "envelope": [e.as_json() for e in envelopes],
            }
        )
        return
    for path in written:
        click.echo(f"wrote {path}")
    for note in left_alone:
        click.echo(f"left alone: {note}")
    for envelope in envelopes:
        click.echo(envelope.text())


@main.command()
@click.argument("cell", required=False, type=click.Path(dir_okay=False))
@click.option("--out", "out_dir", default="generated", show_default=True, type=click.Path(file_okay=False))
def diff(cell: str | None, out_dir: str) -> None:
    """Unified diff of fresh output against OUT; exit 1 when they differ. No CELL: every bundled
    example cell (all the cells whose output is committed under generated/)."""
    from pathlib import Path

    from codegen.cell import EXAMPLES_DIR
    from codegen.emit import EmitError
    from codegen.generate import diff as run_diff

    bundled = [p for folder in ("", "pallets/", "conveyor/", "laser/") for p in EXAMPLES_DIR.glob(f"{folder}*.toml")]
    paths = [cell] if cell is not None else sorted(bundled)
    text = ""
    for path in paths:
        model = _load(path)
        try:
            text += run_diff(model, Path(out_dir))
        except EmitError as exc:
            raise UserError(f"{model.source}: {exc}") from None
    if text:
        click.echo(text, nl=False)
        sys.exit(1)


@main.command()
@click.argument("cell", required=False, type=click.Path(dir_okay=False))
@click.argument("files", nargs=-1, type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--target",
    "targets",
    multiple=True,
    type=click.Choice(target_names()),
    help="Only this target (repeatable).",
)
@click.option("--cases", default=1000, show_default=True, help="Random readings per station.")
@step_limit_option("A run taking more steps is a runaway: a mismatch; that target's remaining cases are skipped.")
@click.option("--seed", default=0, show_default=True)
@click.option(
    "--jobs",
    default=0,
    show_default=True,
    type=click.IntRange(min=0),
    help="Worker processes (0: one per CPU).",
)
@click.option("--json", "as_json", is_flag=True, help="Machine-readable report.")
def verify(
    cell: str | None,
    files: tuple[str, ...],
    targets: tuple[str, ...],
    cases: int,
    step_limit: int,
    seed: int,
    jobs: int,
    as_json: bool,
) -> None:
    """Interpret programs on random, edge, out-of-limit and invalid readings; compare with the reference.

    Without FILES the programs are generated fresh (with an extra station of edge-case poses);
    with FILES (a .src finds its .dat beside it) the files on disk are verified.
    """
    import os
    import re
    import time
    from pathlib import Path

    from codegen import verify as v
    from codegen import verify_runs as runs
    from codegen.dialects import is_companion
    from codegen.dialects.core.values import RunError

    if cell is not None and Path(cell).suffix.lower() != ".toml":
        files = (cell, *files)
        cell = None
    model = _load(cell)
    files_given = bool(files)
    if cases < 0:
        raise UserError("--cases must be >= 0")
    from codegen.pallet.verify import PalletFilesError, pallet_section

    try:
        pallets, files = pallet_section(model, files, targets, seed)  # the stacking programs' own cases
    except PalletFilesError as exc:
        raise UserError(str(exc)) from None
    except RunError as exc:  # a pallet program that cannot be loaded here
        raise click.ClickException(str(exc)) from None
    from codegen.conveyor.verify import conveyor_section

    try:
        conveyors, files = conveyor_section(model, files, targets, seed)  # against simulated belts
    except RunError as exc:
        raise click.ClickException(str(exc)) from None
    from codegen.laser.verify import laser_section

    try:
        lasers, files = laser_section(model, files, targets, seed)  # against simulated laser sensors
    except RunError as exc:
        raise click.ClickException(str(exc)) from None
    sections = {"pallets": pallets, "conveyors": conveyors, "lasers": lasers}
    if not model.stations and files:  # files that are none of this cell's programs: nothing would judge them
        names = ", ".join(Path(f).name for f in files)
        raise UserError(
            f"{names}: not a program of {model.name}'s pallets, conveyor or laser station (named as the program)"
        )
    if any(x is not None for x in sections.values()) and (not model.stations or (files_given and not files)):
        _finish_sections(model, sections, as_json)
    from codegen.emit import EmitError
    from codegen.generate import GenerateError, check_envelope

    try:
        check_envelope(model, None)  # the reference's joints need every taught pose within the arm's reach
    except GenerateError as exc:
        raise UserError(f"{model.source}: {exc}") from None
    verify_cell = model
    if files:
        sources = []
        for f in files:
            path = Path(f)
            if is_companion(path):
                continue
            try:
                name = targets[0] if len(targets) == 1 else v.target_of_file(path)
                source = runs.file_source(name, path)
                source.load()  # a syntax error is reported before any case runs
                sources.append(source)
                stamp = re.search(r"sha256 ([0-9a-f]{64})", source.text)
                if stamp and stamp.group(1) != model.sha256:
                    click.echo(
                        f"warning: {path} says it was generated from another cell file (sha256 "
                        f"{stamp.group(1)[:12]}...) than {model.source}; verifying against {model.name}",
                        err=True,
                    )
            except (ValueError, RunError) as exc:
                raise UserError(str(exc)) from None
        from codegen.generate import mixed_stamps

        mixed = mixed_stamps([Path(f) for source in sources for f in source.files])
        if mixed:
            click.echo(f"warning: {mixed}", err=True)
        if not sources:
            raise UserError("no program to verify: a data file is read together with its program; give the program")
    else:
        names = list(targets) or list(model.targets)
        verify_cell = v.edge_cell(model) if model.robot is None else model
        try:
            sources = runs.fresh_sources(verify_cell, names)
        except EmitError as exc:
            raise UserError(f"{model.source}: {exc}") from None
    case_list = v.build_cases(verify_cell, cases, seed)
    edge = None if files else v.edge_only_cell(model)  # with an arm: the edge poses' programs, without it
    if edge is not None:
        edge_sources = runs.fresh_sources(edge, names)
        edge_cases = v.build_cases(edge, cases, seed)
    total = len(case_list) * len(sources)
    workers = jobs if jobs > 0 else (os.cpu_count() or 1)
    start = time.perf_counter()
    try:
        if sys.stderr.isatty():
            with click.progressbar(length=total, label="verifying", file=sys.stderr, show_pos=True) as bar:
                reports = runs.run_verify(
                    model, sources, case_list, workers, bar.update, verify_cell, step_limit=step_limit
                )
        else:
            reports = runs.run_verify(model, sources, case_list, workers, None, verify_cell, step_limit=step_limit)
        if edge is not None:
            extra = runs.run_verify(
                edge, edge_sources, edge_cases, workers, None, edge, sweep=False, step_limit=step_limit
            )
            reports = [runs.merge_reports([r, e]) for r, e in zip(reports, extra, strict=True)]
    except RunError as exc:  # a program that cannot be loaded here (e.g. nested too deeply)
        raise click.ClickException(str(exc)) from None
    wall = time.perf_counter() - start
    summaries = [r.summary() for r in reports]
    ok = all(s["mismatches"] == 0 for s in summaries) and all(x is None or x.ok for x in sections.values())
    if as_json:
        _dump(
            {
                "cell": model.name,
                "seed": seed,
                "random_per_station": cases,
                "ok": ok,
                "wall_seconds": wall,
                "workers": workers,
                "targets": summaries,
                **{key: x.summaries() for key, x in sections.items() if x is not None},
            }
        )
    else:
        for line in runs.report_lines(model, verify_cell, case_list, cases, seed, summaries, wall, workers):
            click.echo(line)
        for section in sections.values():
            for line in [] if section is None else section.lines():
                click.echo(line)
    sys.exit(0 if ok else 1)


def _finish_sections(model, named: dict, as_json: bool) -> None:
    """A cell (or files) with pallet, conveyor or laser programs only: report them and exit (0: all matched)."""
    sections = [s for s in named.values() if s is not None]
    if not any(s.reports for s in sections):
        raise UserError(
            f"{model.source}: no program verified (no pallet, conveyor or laser program for the targets asked)"
        )
    ok = all(s.ok for s in sections)
    if as_json:
        out = {"cell": model.name, "ok": ok}
        out.update({key: x.summaries() for key, x in named.items() if x is not None})
        _dump(out)
    else:
        for section in sections:
            for line in section.lines():
                click.echo(line)
    sys.exit(0 if ok else 1)

