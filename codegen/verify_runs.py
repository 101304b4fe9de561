"""Programs for verify (parsed once, as picklable sources for worker processes), the runs in parallel, the
sweep of unknown station ids, merged reports and the text report."""

from __future__ import annotations

import gc
from dataclasses import dataclass
from pathlib import Path

from codegen.controllers import Target, get_target
from codegen.dialects import get_dialect
from codegen.dialects.core.machine import DEFAULT_STEP_LIMIT, Program, frozen_heap
from codegen.dialects.core.values import RunError, StepLimitError
from codegen.emit import Emitter
from codegen.guard import UNKNOWN_STATION_TEXT
from codegen.kinds.stations.base import Case
from codegen.model.cell import STATION_ID_MAX, Cell
from codegen.protocol import station_kinds
from codegen.robot.expect import arm_of, home_move
from codegen.verify import TargetReport, UnknownStation, inputs_for, run_options, verify


def load_program(target: Target, text: str, filename: str, companions: dict[str, str] | None = None) -> Program:
    try:
        program = get_dialect(target.dialect).load(text, filename, companions)
    except RecursionError:
        raise RunError(f"{filename}: statements or expressions nested too deeply to run here") from None
    return program


def load_program_file(target: Target, path: Path) -> Program:
    """A program file on disk (with its companion files found beside it)."""
    return file_source(target.name, path).load()


def fresh_programs(cell: Cell, targets: list[str]) -> dict[str, tuple[Program, list[str]]]:
    """Fresh output of the cell, parsed: target -> (program, file names)."""
    return {s.target: (s.load(), list(s.files)) for s in fresh_sources(cell, targets)}


@dataclass(frozen=True)
class ProgramSource:
    """A program as text (picklable), so that worker processes can parse it themselves."""

    target: str
    text: str
    filename: str
    companions: tuple[tuple[str, str], ...]  # (suffix, text) of data files read with the program
    files: tuple[str, ...]

    def load(self) -> Program:
        return load_program(get_target(self.target), self.text, self.filename, dict(self.companions))


def fresh_sources(cell: Cell, targets: list[str]) -> list[ProgramSource]:
    from codegen.render import render

    files = render(cell, targets)
    out = []
    for name in targets:
        companions = get_dialect(get_target(name).dialect).companions
        mine = [f for f in files if f.relpath.split("/")[1] == name]
        main = next(f for f in mine if not f.relpath.endswith(companions))
        data = tuple(("." + f.relpath.rsplit(".", 1)[1], f.text) for f in mine if f.relpath.endswith(companions))
        out.append(ProgramSource(name, main.text, f"<fresh>/{main.relpath}", data, tuple(f.relpath for f in mine)))
    return out


def file_source(target: str, path: Path) -> ProgramSource:
    """A program on disk with the companion files found beside it (e.g. a data list beside its program)."""
    data, files = [], [str(path)]
    for suffix in get_dialect(get_target(target).dialect).companions:
        companion = path.with_suffix(suffix)
        if companion.exists():
            data.append((suffix, _read(companion)))
            files.append(str(companion))
    return ProgramSource(target, _read(path), str(path), tuple(data), tuple(files))


def _read(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise RunError(f"{path}: not UTF-8 text (byte {exc.start}): codegen reads programs as UTF-8") from None
    except OSError as exc:
        raise RunError(f"{path}: cannot read: {exc.strerror or exc}") from None


_LOADED: dict[ProgramSource, Program] = {}
ONE_PROGRAM_FROM = 300  # stations: from here a worker holds one target's program at a time (issue 16's memory)


def sweep_unknown_ids(
    cell: Cell, targets: list[str], programs: dict, ids: range, step_limit: int = DEFAULT_STEP_LIMIT
) -> list[TargetReport]:
    """Every id of `ids` that is not a station of the cell must halt with the unknown-station message
    before any move: an extra dispatch branch (a misread barcode that moves the robot) is caught
    wherever in the barcode range it is, not only at sampled ids."""
    known = {s.id for s in cell.stations}
    reports = []
    for name in targets:
        target = get_target(name)
        program, files = programs[name]
        text = Emitter(target).string(UNKNOWN_STATION_TEXT)
        arm = arm_of(cell, name)  # the same for every id
        before = 0 if home_move(cell, name) is None else 1  # the home move comes first
        report = TargetReport(name, files)
        for station_id in ids:
            if station_id in known:
                continue
            report.unknown_ids += 1
            try:
                case = Case("unknown_station", UnknownStation(station_id))
                inputs, options = inputs_for(cell, target, case.reading), run_options(cell, target, case)
                got = program.run(inputs, step_limit=step_limit, arm=arm, **options)
                problem = None
                if len(got.moves) != before or not got.halted or got.halt_message != f"{text}{station_id}":
                    problem = f"{len(got.moves) - before} moves, halt message {got.halt_message!r}"
            except StepLimitError as exc:
                report.mismatches += 1
                report.first_mismatches.append(f"unknown station id {station_id}: {exc}; the sweep stopped")
                break
            except RunError as exc:
                problem = f"run error: {exc}"
            if problem is not None:
                report.mismatches += 1
                if len(report.first_mismatches) < 10:
                    report.first_mismatches.append(f"unknown station id {station_id}: {problem}")
        reports.append(report)
    return reports


def _rounds(sources: list) -> list[list]:
    """The (row, source) pairs in rounds of at most one program per target: two programs of one target (a
    socket program and its Script-node twin) are two rows, each run on every case (the reference runs once per
    round and case)."""
    rounds: list[list] = []
    for row, source in sources:
        free = next((r for r in rounds if all(s.target != source.target for _, s in r)), None)
        if free is None:
            rounds.append(free := [])
        free.append((row, source))
    return rounds


def _verify_chunk(args) -> list[tuple[int, TargetReport]]:
    """One chunk of cases, or of the id sweep, on every source (row, source): each report with its row."""
    cell, verify_cell, sources, work, step_limit = args
    if len(cell.stations) >= ONE_PROGRAM_FROM and any(loaded not in [s for _, s in sources] for loaded in _LOADED):
        _LOADED.clear()  # a large cell's next target: the last one's program goes (run_verify's order)
        gc.collect()
    out = []
    for round_ in _rounds(sources):
        programs = {}
        for _row, source in round_:
            if source not in _LOADED:
                _LOADED[source] = source.load()
            programs[source.target] = (_LOADED[source], list(source.files))
        targets = [s.target for _, s in round_]
        if isinstance(work, range):
            with frozen_heap():
                reports = sweep_unknown_ids(verify_cell or cell, targets, programs, work, step_limit)
        else:
            reports = verify(cell, targets, programs, work, verify_cell=verify_cell, step_limit=step_limit)
        out += [(row, report) for (row, _), report in zip(round_, reports, strict=True)]
    return out


def merge_reports(parts: list[TargetReport]) -> TargetReport:
    out = TargetReport(parts[0].target, parts[0].files)
    for part in parts:
        out.cases += part.cases
        out.mismatches += part.mismatches
        out.halts += part.halts
        out.boundary += part.boundary
        out.moves += part.moves
        out.pos_errors.extend(part.pos_errors)
        out.rot_errors.extend(part.rot_errors)
        out.first_mismatches.extend(part.first_mismatches[: 10 - len(out.first_mismatches)])
        out.seconds += part.seconds
        out.unknown_ids += part.unknown_ids
        out.arm.merge(part.arm)
        for name, kind in station_kinds().items():
            kind.merge_stats(out.kind_stats[name], part.kind_stats[name])
        for key, count in part.categories.items():
            out.categories[key] = out.categories.get(key, 0) + count
    return out


CHUNK_CASES = 2000


def run_verify(
    cell: Cell,
    sources: list[ProgramSource],
    cases: list[Case],
    jobs: int = 1,
    progress=None,
    verify_cell: Cell | None = None,
    sweep: bool = True,
    step_limit: int = DEFAULT_STEP_LIMIT,
) -> list[TargetReport]:
    """Verify every source on every case and, with `sweep`, every id of the barcode range that is not
    a station (sweep_unknown_ids), in `jobs` processes; `seconds` is the time spent running
    one dialect's cases (summed over workers), so cases/seconds is the per-dialect speed."""
    # at most CHUNK_CASES cases per task: a worker holds one chunk's expectations at a time (issue 16's memory)
    chunk = max(1, min(CHUNK_CASES, -(-len(cases) // max(4, 2 * jobs))))
    # a large cell's programs one target after another: a worker then holds one of them at a time (it lets the
    # last one go when a task of another comes), at the cost of the reference once per target and case
    rows = list(enumerate(sources))  # each source is a row of the report, even two of one target
    groups = [[r] for r in rows] if len(cell.stations) >= ONE_PROGRAM_FROM and len(sources) > 1 else [rows]
    tasks = [
        (cell, verify_cell, group, cases[i : i + chunk], step_limit)
        for group in groups
        for i in range(0, len(cases), chunk)
    ]
    if sweep:
        step = -(-(STATION_ID_MAX + 1) // max(2, jobs))
        ranges = [range(i, min(i + step, STATION_ID_MAX + 1)) for i in range(0, STATION_ID_MAX + 1, step)]
        tasks += [(cell, verify_cell, group, ids, step_limit) for group in groups for ids in ranges]
        if len(groups) > 1:  # each target's cases then its sweep, target by target
            tasks.sort(key=lambda task: task[2][0][0])
    parts: list[list[TargetReport]] = [[] for _ in sources]

    def collect(reports: list[tuple[int, TargetReport]]) -> None:
        for row, part in reports:
            parts[row].append(part)
            if progress is not None:
                progress(part.cases)

    if jobs <= 1:
        for task in tasks:
            collect(_verify_chunk(task))
    elif len(groups) >= jobs > 1 and len(groups) > 1:
        # as many targets as workers or more: each worker runs whole targets, loading each program once
        # (the workers sharing one target would each load it: for 1,000 stations that is 5-9 s a target)
        worker_of = {id(group): i % jobs for i, group in enumerate(groups)}
        for reports in _run_pinned(tasks, [worker_of[id(task[2])] for task in tasks], jobs, progress):
            for row, part in reports:  # progress was told as each chunk ended
                parts[row].append(part)
    else:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(max_workers=jobs, mp_context=_fork()) as pool:
            for reports in pool.map(_verify_chunk, tasks):
                collect(reports)
    return [merge_reports(part) for part in parts]


def _fork():
    """Workers forked where the system can (they start at once, with the parent's modules)."""
    import multiprocessing

    return multiprocessing.get_context("fork") if "fork" in multiprocessing.get_all_start_methods() else None


def _forkserver():
    """Workers started from a clean server process where the system has one: a pool's worker forked from
    this process after another pool's threads started could inherit a lock one of them held."""
    import multiprocessing

    if "forkserver" not in multiprocessing.get_all_start_methods():
        return None
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(["codegen.verify_runs"])  # imported once, in the server
    return context


def _run_pinned(tasks: list, workers: list[int], jobs: int, progress) -> list[list[TargetReport]]:
    """Each task in the worker process given for it (one single-process pool each, so a worker's tasks
    run in their order); the results in the tasks' order, progress as each chunk ends."""
    from concurrent.futures import ProcessPoolExecutor, as_completed

    pools = [ProcessPoolExecutor(max_workers=1, mp_context=_forkserver()) for _ in range(jobs)]
    try:
        futures = [pools[worker].submit(_verify_chunk, task) for task, worker in zip(tasks, workers, strict=True)]
        if progress is not None:
            for future in as_completed(futures):
                for _row, part in future.result():
                    progress(part.cases)
        return [future.result() for future in futures]
    finally:  # after an error, without waiting for the other workers' chunks
        for pool in pools:
            pool.shutdown(wait=False, cancel_futures=True)


def row_labels(summaries: list[dict]) -> list[str]:
    """Each report row's name: its target, and its program's file where a target has several rows."""
    targets = [s["target"] for s in summaries]
    return [
        f"{s['target']} {Path(s['files'][0]).name}" if targets.count(s["target"]) > 1 else s["target"]
        for s in summaries
    ]


def report_lines(model: Cell, verify_cell: Cell, case_list: list, cases: int, seed: int, summaries, wall, workers):
    """`codegen verify`'s text report: the cell, one line per target (and its first mismatches), the
    kinds' own tables, the arm's margins, the runs and the verdict."""
    yield (
        f"cell {model.name}: {len(verify_cell.stations)} stations, {len(case_list)} readings per target "
        f"({cases} random per station, seed {seed})"
    )
    yield (
        f"{'target':<8}{'cases':>7}{'fail':>6}{'halts':>7}{'bound':>7}{'pos max mm':>12}"
        f"{'pos p99':>10}{'rot max deg':>13}{'rot p99':>10}{'cases/s':>9}"
    )
    labels = row_labels(summaries)
    for s, label in zip(summaries, labels, strict=True):
        yield (
            f"{label:<8}{s['cases']:>7}{s['mismatches']:>6}{s['halts']:>7}{s['boundary_cases']:>7}"
            f"{s['position_error_mm']['max']:>12.2e}{s['position_error_mm']['p99']:>10.2e}"
            f"{s['orientation_error_deg']['max']:>13.2e}{s['orientation_error_deg']['p99']:>10.2e}"
            f"{s['cases_per_second'] or 0:>9.0f}"
        )
        for line in s["first_mismatches"]:
            yield f"  MISMATCH {line}"
    for kind in station_kinds().values():  # each kind's own figures, as a table of its own
        yield from kind.report_lines(summaries)
    for s, label in zip(summaries, labels, strict=True):  # the arm's joints over every verified move
        if "arm" in s:
            arm = s["arm"]
            yield (
                f"arm {label}: {arm['moves']} moves solved to joints; least margin to a joint limit "
                f"{arm['joint_margin_deg']:.1f} deg, of axis 5 from its singularity {arm['wrist_margin_deg']:.1f} deg"
            )
    swept = sum(s["unknown_ids_checked"] for s in summaries)
    yield (
        f"{sum(s['cases'] for s in summaries)} runs and {swept} runs of the other station ids "
        f"(every id 0..{STATION_ID_MAX} that is not a station must halt before moving) in {wall:.1f} s wall, "
        f"{workers} worker(s); cases/s = one dialect on one core"
    )
    ok = all(s["mismatches"] == 0 for s in summaries)
    yield "verify: all traces match the reference" if ok else "verify: MISMATCHES"
