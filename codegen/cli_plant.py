"""The commands on a plant (a folder of cells or its codegen.toml): each cell's generate, diff, verify or check in
one table."""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import click

from codegen.cli_base import UserError, dump
from codegen.plant.config import PLANT_FILE, Plant, PlantError, discover, load_plant
from codegen.plant.progress import progress_bars, wanted
from codegen.plant.results import CellResult, Line, PlantReport, cell_kinds, error_result
from codegen.plant.run import plant_report, run_plant

# how a --timings file (PlantReport.timings, written below) begins: a file that does not is not replaced
TIMINGS_MARKS = (b'{\n  "command": "verify",\n  "plant": "',)


def is_plant_argument(path: str | None) -> bool:
    """A plant rather than one cell: a codegen.toml, or a folder (generate, diff, verify)."""
    return path is not None and (Path(path).is_dir() or Path(path).name == PLANT_FILE)


def is_plant_folder(path: str) -> bool:
    """check's FILES argument as a plant: a codegen.toml, or a folder holding one or a cell file (a folder of
    program files alone stays a folder of programs)."""
    folder = Path(path)
    if folder.name == PLANT_FILE and folder.is_file():
        return True
    return folder.is_dir() and ((folder / PLANT_FILE).is_file() or bool(discover(folder.resolve())[0]))


def plant_of(path: str) -> Plant:
    try:
        plant = load_plant(path)
    except PlantError as exc:
        raise UserError(str(exc)) from None
    if not plant.cells:
        raise UserError(f"{path}: no cell files here (a cell file is a .toml with a [cell] table)")
    return plant


def given(name: str) -> bool:
    """Whether the option was given on the command line (else the plant's default applies)."""
    source = click.get_current_context().get_parameter_source(name)
    return source is not None and source.name not in ("DEFAULT", "DEFAULT_MAP")


def out_of(plant: Plant, out_dir: str) -> Path:
    """--out where given, else the plant's `out`, else generated/ in the plant's folder."""
    if given("out_dir"):
        return Path(out_dir)
    return plant.output()


def finish(
    report: PlantReport, plant: Plant, form: str = "text", before: list[str] = (), timings: str | None = None
) -> None:
    """Print the table, its JSON (no times) or a report format's text (--format junit, sarif, github: every cell's
    findings), write the times where asked, and exit with the plant's code."""
    if timings is not None:
        from codegen.writefile import WriteRefused, write_own

        try:
            write_own(Path(timings), json.dumps(report.timings(), indent=2) + "\n", TIMINGS_MARKS)
        except WriteRefused as exc:
            raise UserError(f"--timings: {exc}") from None
        except OSError as exc:
            raise UserError(f"--timings {timings}: cannot write: {exc.strerror or exc}") from None
    if form == "json":
        dump(report.as_json())
    elif form == "text":
        for text in before:
            click.echo(text, nl=False)
        for line in report.lines():
            click.echo(line)
    else:
        from codegen.plant.findings import cell_findings
        from codegen.reports.formats import write
        from codegen.reports.paths import repository_root

        results = [
            cell_findings(result, report.command, plant, path)
            for result, path in zip(report.results, plant.cells, strict=True)
        ]
        click.echo(write(form, results, repository_root()), nl=False)
    sys.exit(report.exit_code)


def _form(as_json: bool) -> str:
    return "json" if as_json else "text"


def _cell_step(plant: Plant, path: Path, work) -> CellResult:
    """Load a cell and do `work(model, label, start)`; a cell or a command that refuses it is an error row."""
    from codegen.cli_base import load

    label = plant.label(path)
    start = time.perf_counter()
    try:
        model = load(path)
        return work(model, label, start)
    except click.ClickException as exc:
        return error_result(label, exc.message, time.perf_counter() - start)


def _targets(plant: Plant, model, asked: tuple[str, ...] = ()) -> list[str]:
    chosen = asked or plant.targets
    return [t for t in model.targets if not chosen or t in chosen]


def generate_plant(path: str, targets: tuple[str, ...], out_dir: str, as_json: bool) -> None:
    from codegen.cli_base import write_cell
    from codegen.robot.expect import home_margins

    plant = plant_of(path)
    out = out_of(plant, out_dir)

    def work(model, label, start) -> CellResult:
        names = _targets(plant, model, targets)
        if not names:
            return CellResult(label, model.name, [Line(label, "-", cell_kinds(model), None, "skipped", 0.0)])
        written, left_alone, envelopes = write_cell(model, names, out)
        homes = home_margins(model, names)
        data = {
            "written": [str(p) for p in written],
            "left_alone": left_alone,
            "home": [h.as_json() for h in homes],
            "envelope": [e.as_json() for e in envelopes],
        }
        margins = "\n".join([*(h.text() for h in homes), *(e.text() for e in envelopes)])  # as one cell's generate
        seconds = time.perf_counter() - start
        line = Line(label, ",".join(names), cell_kinds(model), None, "written", seconds, margins)
        return CellResult(label, model.name, [line], data, notes=[f"left alone: {n}" for n in left_alone])

    finish(run_plant(plant, "generate", lambda p, _: _cell_step(plant, p, work), wanted()), plant, _form(as_json))


def diff_plant(path: str, out_dir: str, as_json: bool) -> None:
    from codegen.cli_base import diff_cell

    plant = plant_of(path)
    out = out_of(plant, out_dir)
    texts: list[str] = []

    def work(model, label, start) -> CellResult:
        text = diff_cell(model, out)
        texts.append(text)
        files = sum(line.startswith("+++ ") or line.startswith("Only in ") for line in text.splitlines())
        line = Line(
            label,
            ",".join(model.targets),
            cell_kinds(model),
            None,
            "differs" if text else "ok",
            time.perf_counter() - start,
            f"{files} file(s) differ from {out}" if text else "",
        )
        return CellResult(label, model.name, [line], {"diff": text})

    report = run_plant(plant, "diff", lambda p, _: _cell_step(plant, p, work), wanted())
    finish(report, plant, _form(as_json), texts)


def markdown_diff_plant(path: str, out_dir: str, no_verify: bool) -> None:
    """diff --format markdown of a plant: one document over its changed cells (each cell's programs as for one cell,
    the new programs of a changed cell verified, with the plant's cases, seed and step limit, unless no_verify);
    exit codes as the plant's diff table has them."""
    from codegen.reports.markdown import plant_markdown
    from codegen.reports.program_diff import add_verdicts, cell_change
    from codegen.verify import engine

    plant = plant_of(path)
    out = out_of(plant, out_dir)
    changes = {}
    defaults = engine.Options()
    options = engine.Options(
        defaults.cases if plant.cases is None else plant.cases,
        defaults.seed if plant.seed is None else plant.seed,
        step_limit=plant.step_limit,
    )

    def work(model, label, start) -> CellResult:
        try:
            change = cell_change(model, out)
            if change.programs and not no_verify:
                add_verdicts(change, engine.verify_cell(model, options=options))
        except engine.CELL_ERRORS as exc:
            return error_result(label, f"{model.source}: {exc}", time.perf_counter() - start, model.name)
        change.cell_file = label  # the plant's document names cell files from the plant's folder
        changes[label] = change
        word = "differs" if change.programs else "ok"
        line = Line(label, ",".join(model.targets), cell_kinds(model), None, word, time.perf_counter() - start)
        return CellResult(label, model.name, [line])

    report = run_plant(plant, "diff", lambda p, _: _cell_step(plant, p, work), wanted())
    errors = [(r.cell, r.lines[0].message) for r in report.results if r.cell not in changes]
    click.echo(plant_markdown(report.plant, list(changes.values()), errors), nl=False)
    sys.exit(report.exit_code)


def verify_plant(
    path: str, targets, cases, seed, step_limit, jobs, scheduler, form: str, use_cache: bool, cache_dir, timings=None
) -> None:
    from codegen.plant.cache import Cache, cache_folder
    from codegen.plant.executors import ClusterError, executor_for
    from codegen.plant.verify import PlantVerify, verify_plant

    plant = plant_of(path)
    if timings is not None and not Path(timings).absolute().parent.is_dir():  # said before any case runs
        raise UserError(f"--timings {timings}: no folder {Path(timings).absolute().parent}")
    if timings is not None:
        from codegen.writefile import WriteRefused, check_own

        try:
            check_own(Path(timings), TIMINGS_MARKS)
        except WriteRefused as exc:
            raise UserError(f"--timings: {exc}") from None
    how = PlantVerify(
        tuple(targets) or plant.targets,
        cases if given("cases") or plant.cases is None else plant.cases,
        seed if given("seed") or plant.seed is None else plant.seed,
        step_limit if step_limit is not None else plant.step_limit,
        jobs,
        Cache(cache_folder(cache_dir, plant.cache, plant.root)) if use_cache else None,
    )
    start = time.perf_counter()
    try:
        with executor_for(scheduler, jobs) as executor, progress_bars(len(plant.cells), wanted()) as bars:
            results = verify_plant(plant, how, executor, bars)
    except ClusterError as exc:
        raise UserError(f"--scheduler: {exc}") from None
    finish(plant_report(plant, "verify", results, time.perf_counter() - start), plant, form, timings=timings)


def check_plant(path: str, out_dir: str | None, form: str) -> None:
    """Each cell's programs in the output folder, one row per target, checked against the cell's arm."""
    from dataclasses import replace
    from functools import partial

    from codegen.checkfiles import check_files
    from codegen.controllers import get_target
    from codegen.plant.findings import stored
    from codegen.render import cell_dir, plans
    from codegen.reports.findings import CellResult as Findings
    from codegen.reports.from_check import check_result
    from codegen.robot.expect import arm_of

    plant = plant_of(path)
    out = Path(out_dir) if out_dir is not None else plant.output()

    def step(cell_path: Path, _) -> CellResult:
        from codegen.cli_base import load

        label = plant.label(cell_path)
        start = time.perf_counter()
        try:
            model = load(cell_path)
        except click.ClickException as exc:
            return error_result(label, exc.message, time.perf_counter() - start)
        lines, data = [], {}
        found = Findings("check", label, str(cell_path))
        for target in _targets(plant, model):
            begun = time.perf_counter()
            folder = out / cell_dir(model) / target
            kinds = cell_kinds(model)
            if not folder.is_dir():
                message = f"{folder}: no programs here (`codegen generate {path}` writes them)"
                lines.append(Line(label, target, kinds, None, "error", 0.0, message))
                continue
            # a program that starts at a routine of its own (a module loaded into the production task, which has
            # the main) is checked from there, as the kind's plan says
            entries = {f.name: p.entry for p in plans(model, get_target(target)) if p.entry for f in p.files}
            try:
                checked = check_files((str(folder),), target, arm_of(model, target), None, partial(_entry, entries))
            except click.ClickException as exc:
                lines.append(Line(label, target, kinds, None, "error", time.perf_counter() - begun, exc.message))
                continue
            word = {0: "clean", 1: "findings", 2: "error"}[checked.code]
            text = "\n".join(f.text() for f in checked.findings)
            lines.append(Line(label, target, kinds, None, word, time.perf_counter() - begun, text))
            data[target] = {"findings": [f.as_json() for f in checked.findings], "counts": checked.counts}
            programs = check_result(checked.programs, checked.findings).cases
            found.cases += [replace(case, cell=model.name, program=Path(case.program).name) for case in programs]
        return CellResult(label, model.name, lines, data, findings=stored(found, plant))

    finish(run_plant(plant, "check", step, wanted()), plant, form)


def _entry(entries: dict[str, str], names: list[str]) -> str | None:
    """The entry routine of the program of these files (by a file's name), None where it starts at its main."""
    return next((entries[Path(n).name] for n in names if Path(n).name in entries), None)
