"""The programs verify runs: fresh from the cell (each kind renders only its own) or the files given, each matched
to the kind and program of the cell it is (by its file name), as picklable sources a worker loads itself."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from codegen.controllers import get_target, target_of_language, target_of_suffix
from codegen.dialects import dialect_of_suffix, get_dialect
from codegen.dialects.core.files import FRESH, SourceFile, read_source
from codegen.dialects.core.values import RunError
from codegen.output import mixed_set, stamp_of
from codegen.render import cell_dir, plans, render_plan


class ProgramFilesError(ValueError):
    """Files given to verify that are not the cell's programs (or cannot be told apart); exit 2."""


@dataclass(frozen=True)
class ProgramSource:
    """One program as text (picklable): the kind and target it is for, which of the kind's programs (its plan
    index), its files (the program file first) and where they come from; `model` is the cell it was made from
    and is judged against (None: the cell verify was asked about) and `row` the report row it counts in."""

    kind: str
    target: str
    ident: str
    index: int
    files: tuple[SourceFile, ...]
    origin: tuple[str, ...]  # the files' paths as given, or <fresh>/<cell>/<target>/<file>
    row: int = 0
    model: object = field(default=None, compare=False)
    sweep: bool = True  # the kind's bulk runs too (VerifyPlan.sweeps), not only its cases
    entry: str | None = None  # the routine a run starts at (ProgramPlan.entry; None: the language's entry)

    @property
    def label(self) -> str:
        return Path(self.origin[0]).name

    def load(self):
        return load_files(get_target(self.target), list(self.files), self.origin[0], self.entry)


def fresh_sources(cell, targets: list[str], model=None, row_of=None, only=None, sweep=True) -> list[ProgramSource]:
    """Every program of every kind (of the kinds `only`, if given) for the targets, rendered from `cell`: each
    kind's own files, and the files of the target's other programs rendered here that its language reads with it
    from their common folder (Dialect.shared_among: the data lists of its folder a program uses)."""
    out = []
    for name in targets:
        target = get_target(name)
        dialect = get_dialect(target.dialect)
        rendered_plans = [(plan, render_plan(cell, target, plan)) for plan in plans(cell, target, only)]
        folder = [SourceFile(f"{FRESH}{r.relpath}", r.text) for _plan, rendered in rendered_plans for r in rendered]
        for plan, rendered in rendered_plans:
            own = [SourceFile(f"{FRESH}{r.relpath}", r.text) for r in rendered]
            names = {f.name for f in own}
            shared = dialect.shared_among(own[0], [f for f in folder if f.name not in names])
            files = (*own, *shared)
            origin = tuple(f"{FRESH}{cell_dir(cell)}/{name}/{Path(f.name).name}" for f in files)
            row = len(out) if row_of is None else row_of(plan, name)
            entry = plan.entry
            out.append(ProgramSource(plan.kind, name, plan.ident, plan.index, files, origin, row, model, sweep, entry))
    return out


def file_sources(cell, paths: list[Path], targets: tuple[str, ...]) -> tuple[list[ProgramSource], list[str]]:
    """The given files grouped into programs (each language's rule: a program file with its data list, ...) and
    each matched to the cell's program of that name (another name: the cell's station program, where it has one);
    warnings (another cell file's stamp). A file that is none of the cell's programs is a ProgramFilesError."""
    by_target: dict[str, list[Path]] = {}
    for path in paths:
        target = _target_of(path, targets)
        if target not in cell.targets:  # the cell makes no program for it: nothing to verify the file against
            raise ProgramFilesError(
                f"{path}: a program for {target}, and cell {cell.name} ({cell.source}) has no {target} target "
                f"(its targets: {', '.join(cell.targets)}): verify it with its own cell"
            )
        by_target.setdefault(target, []).append(path)
    out, warnings = [], []
    for target_name, group in by_target.items():
        target = get_target(target_name)
        dialect = get_dialect(target.dialect)
        known = {}  # program file name -> (plan, its file names)
        for plan in plans(cell, target):
            known[plan.files[0].name.lower()] = plan
        # a program under a name of its own (a hand-edited copy) is the station program, where the cell has one
        fallback = next((p for p in known.values() if cell.kinds[p.kind].writer.renamed_copies), None)
        group = [*group, *_companions_beside(group, dialect)]
        try:
            files = [read_source(path, dialect.encodings) for path in group]  # a FIFO, a device: the user's to fix
            programs = dialect.programs(files)
        except RunError as exc:  # a file that cannot be read, a data file given without its program
            raise ProgramFilesError(str(exc)) from None
        for program in programs:
            main = Path(program[0].name)
            plan = known.get(main.name.lower(), fallback)
            if plan is None:
                names = ", ".join(sorted(p.files[0].name for p in known.values())) or "none"
                raise ProgramFilesError(
                    f"{main}: not a program of {cell.name} for {target_name} (its programs, named as "
                    f"`codegen generate` names them: {names})"
                )
            for f in program:
                stamp = stamp_of(f.text)
                if stamp and stamp != cell.sha256:
                    warnings.append(
                        f"{f.name} says it was generated from another cell file (sha256 {stamp[:12]}...) "
                        f"than {cell.source}; verifying against {cell.name}"
                    )
            origin = tuple(f.name for f in program)
            out.append(
                ProgramSource(
                    plan.kind, target_name, plan.ident, plan.index, tuple(program), origin, len(out), entry=plan.entry
                )
            )
    mixed = mixed_set([(f.name, f.text) for source in out for f in source.files])
    return out, [mixed, *warnings] if mixed else warnings


def _companions_beside(paths: list[Path], dialect) -> list[Path]:
    """The data files each given program file brings from its folder (Dialect.beside: a .src's .dat and the data
    lists it uses) that were not given themselves."""
    given = {p.resolve() for p in paths}
    out = []
    for path in paths:
        if path.suffix.lower() not in dialect.suffixes:
            continue
        for candidate in dialect.beside(path):
            if candidate.resolve() not in given:
                out.append(candidate)
                given.add(candidate.resolve())
    return out


def _target_of(path: Path, targets: tuple[str, ...]) -> str:
    """The target of a program file: the one asked for, else the one its suffix names."""
    if len(targets) == 1:
        dialect = dialect_of_suffix(path.suffix)
        if dialect is not None and dialect is not get_dialect(get_target(targets[0]).dialect):
            raise ProgramFilesError(f"{path}: a {dialect.name} file, not a program of --target {targets[0]}")
        return targets[0]
    language = dialect_of_suffix(path.suffix)
    target = target_of_suffix(path.suffix) or (language and target_of_language(language.name))
    if target is None or (targets and target.name not in targets):
        raise ProgramFilesError(f"{path}: cannot tell the target from the suffix; use --target")
    return target.name


def load_file(target, path: Path):
    """One program file on disk, with its data files beside it (RunError: it cannot be read or loaded)."""
    dialect = get_dialect(target.dialect)
    paths = [Path(path), *_companions_beside([Path(path)], dialect)]
    files = [read_source(p, dialect.encodings) for p in paths]
    return load_files(target, dialect.programs(files)[0], str(path))


def load_files(target, files: list[SourceFile], name: str, entry: str | None = None):
    """One program from its files (the program file first), started at `entry` where given (a routine of a program
    without the language's own entry); a program nested deeper than Python's stack is a RunError naming `name`, as
    any other program this tool cannot run."""
    dialect = get_dialect(target.dialect)
    try:
        return dialect.load_files(files) if entry is None else dialect.load_files(files, entry=entry)
    except RecursionError:
        raise RunError(f"{name}: statements or expressions nested too deeply to run here") from None
