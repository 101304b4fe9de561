"""How far `codegen check` and `codegen run` take programs written elsewhere: one row per program of a corpus folder.

The corpus is a folder holding one folder per program (its .src with its .dat, its .mod files, its .script), under
a folder per language (any depth), and a `manifest.tsv` beside them: `folder`, `language`, `repository`, `path`,
`commit`, `note` and, where a person read the program, `judgement` (one of fault, needs-files, valid, with a reason
after a colon) for what a tool cannot tell: whether a name the program uses is defined in a file not collected, is
the program's own mistake, or is valid code the interpreter refuses (read only where the program neither runs nor
is refused by name). The programs themselves stay outside this repository (others' code is not committed here);
the docs list each one's repository, path and commit.

Each program folder goes through `codegen check FOLDER` and `codegen run FOLDER --max-moves 500 --max-seconds 3600`
(each in its own process, with --timeout seconds), and gets one class:

- runs: `run` ended without an error (at its end, a halt, a limit named above, or the step limit of a loop that
  polls what another device sets); a program that reads where the arm stands runs again with the arm's start given;
- refused clearly: a finding or run error that names a construct the interpreter does not model;
- fault: the program's own mistake (judged);
- needs files: it uses routines, data or types of files not collected (judged);
- valid refused: valid code refused (judged);
- traceback: a Python traceback from either command;
- hang: either command still running at the timeout;
- unjudged: an error that needs a person's judgement and has none in the manifest.

Prints a table (one line a program, then the counts by class and language); --markdown prints it as the docs' table.

Run: python benchmarks/public_programs.py CORPUS [--timeout S] [--markdown] [--only FOLDER] [--codegen COMMAND]
"""

from __future__ import annotations

import argparse
import csv
import subprocess
import sys
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

CLASSES = ("runs", "refused clearly", "fault", "needs files", "valid refused", "traceback", "hang", "unjudged")
JUDGED = {"fault": "fault", "needs-files": "needs files", "valid": "valid refused"}
NOT_MODELLED = ("not modelled", "unsupported", "is not simulated", "technology package")
RUN_LIMITS = ["--max-moves", "500", "--max-seconds", "3600"]
# A program that reads where the arm stands (UR get_actual_joint_positions, RAPID CJointT, KRL $AXIS_ACT) runs
# again with the arm's start given: a posture away from the wrist singularity, on the arm DESIGN.md names per
# controller.
START = "0,-90,90,0,45,0"
ARMS = {"KRL": "KR 10 R1100 sixx", "RAPID": "IRB 1600-10/1.45", "URScript": "UR5e"}


@dataclass
class Outcome:
    folder: str
    language: str
    repository: str
    path: str
    commit: str
    klass: str
    reason: str
    note: str = ""


CODEGEN = [str(Path(sys.executable).with_name("codegen"))]


def _codegen(*args: str, timeout: float) -> tuple[int | None, str]:
    """Exit code (None: still running at the timeout) and stdout + stderr of one codegen command."""
    command = [*CODEGEN, *args]
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, ""
    return done.returncode, done.stdout + done.stderr


def _first_error(output: str) -> str:
    """The first error or unsupported line of a command's output (the line a reader sees first)."""
    for line in output.splitlines():
        if "error" in line.lower() or "unsupported" in line.lower():
            return line.strip()
    return output.strip().splitlines()[-1] if output.strip() else ""


def classify(folder: Path, row: dict[str, str], timeout: float) -> Outcome:
    """One program through check and run, and its class."""
    checked_code, checked = _codegen("check", str(folder), timeout=timeout)
    ran_code, ran = _codegen("run", str(folder), *RUN_LIMITS, timeout=timeout)
    started = ran_code not in (None, 0) and "--start" in ran
    if started:
        arm = ["--start", START, "--robot", ARMS[row["language"]]]
        ran_code, ran = _codegen("run", str(folder), *RUN_LIMITS, *arm, timeout=timeout)
    outcome = Outcome(
        row["folder"], row["language"], row["repository"], row["path"], row["commit"], "unjudged", "", row["note"]
    )
    judgement, _, why = (row.get("judgement") or "").partition(":")
    if checked_code is None or ran_code is None:
        outcome.klass, outcome.reason = "hang", "check" if checked_code is None else "run"
    elif "Traceback (most recent call last)" in checked + ran:
        outcome.klass, outcome.reason = "traceback", "check" if "Traceback" in checked else "run"
    elif ran_code == 0 or "step limit" in ran:
        ended = "to its step limit (a loop that waits for what another device sets)" if ran_code else "to its end"
        outcome.klass, outcome.reason = "runs", ended + (" with the arm's start given" if started else "")
    elif any(word in (_first_error(ran) + _first_error(checked)).lower() for word in NOT_MODELLED):
        outcome.klass = "refused clearly"
        first = _first_error(ran)
        outcome.reason = first if any(word in first.lower() for word in NOT_MODELLED) else _first_error(checked)
    elif judgement.strip() in JUDGED:
        outcome.klass, outcome.reason = JUDGED[judgement.strip()], why.strip() or _first_error(ran)
    else:
        outcome.reason = _first_error(ran) or _first_error(checked)
    outcome.reason = outcome.reason.removeprefix("Error: ").replace(f"{folder}/", "")
    return outcome


def read_manifest(corpus: Path) -> list[dict[str, str]]:
    with (corpus / "manifest.tsv").open(newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle, delimiter="\t"))


def table(outcomes: list[Outcome], markdown: bool) -> str:
    """The rows, then the counts by class (all languages, and per language)."""
    lines = []
    if markdown:
        lines += ["| program (repository: path, commit) | language | result |", "|---|---|---|"]
        for one in outcomes:
            shown = f"{one.repository}: `{one.path}` ({one.commit[:10]})" + (f"; {one.note}" if one.note else "")
            reason = f": {one.reason}" if one.reason and one.klass != "runs" else ""
            lines.append(f"| {shown} | {one.language} | {one.klass}{reason.replace('|', '/')} |")
    else:
        for one in outcomes:
            lines.append(f"{one.folder:42} {one.language:9} {one.klass:16} {one.reason[:110]}")
    lines.append("")
    languages = sorted({one.language for one in outcomes})
    counts = {language: Counter(o.klass for o in outcomes if o.language == language) for language in languages}
    total = Counter(o.klass for o in outcomes)
    header = ["class", *languages, "all"]
    if markdown:
        lines += ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for klass in CLASSES:
        cells = [str(counts[language][klass]) for language in languages] + [str(total[klass])]
        lines.append(
            "| " + " | ".join([klass, *cells]) + " |"
            if markdown
            else f"{klass:16} " + " ".join(f"{c:>9}" for c in cells)
        )
    repositories = len({o.repository for o in outcomes})
    lines.append(f"\n{len(outcomes)} programs from {repositories} repositories")
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("corpus", type=Path)
    parser.add_argument("--timeout", type=float, default=120.0, help="seconds per command (default 120)")
    parser.add_argument("--markdown", action="store_true", help="the table as markdown (the docs' form)")
    parser.add_argument("--only", help="one program folder (as in the manifest)")
    parser.add_argument("--codegen", help="the command that runs codegen (default: the one beside this Python)")
    options = parser.parse_args()
    if options.codegen:
        CODEGEN[:] = options.codegen.split()
    rows = [r for r in read_manifest(options.corpus) if options.only in (None, r["folder"])]
    outcomes = []
    for row in rows:
        outcomes.append(classify(options.corpus / row["folder"], row, options.timeout))
        if not options.markdown:
            print(f"{row['folder']}: {outcomes[-1].klass}", file=sys.stderr)
    print(table(outcomes, options.markdown))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
