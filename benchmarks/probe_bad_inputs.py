"""Bad inputs through the command line, one reproducer per class of issue 43, each with a timeout: tracebacks, hangs,
exit codes, user files changed, escape sequences reaching the terminal.

Every case runs `python -m codegen ...` in a folder of its own (made here from the issue's text; the inputs are this
script's own), with a timeout. It is judged on: a traceback in its output; a hang (the timeout); its exit code
against what the case expects (a refusal 2, a program's error 1); a file of the folder (or one beside it) changed,
made or removed that the command does not say it writes; an escape sequence, control character or bidirectional
override in its output. Two cases run two calibrations at once on one cell and expect both results kept.
Run: python benchmarks/probe_bad_inputs.py [--only WORD] [--timeout S] (exit 1 when a case is flagged)
"""

from __future__ import annotations

import argparse
import hashlib
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "codegen" / "examples"
TESTMAT = (EXAMPLES / "pallets" / "testmat_pallet.toml").read_text(encoding="utf-8")
BENCH = (EXAMPLES / "thermometer_bench.toml").read_text(encoding="utf-8")
TERMINAL = re.compile("[\x00-\x08\x0b-\x1f\x7f\x9b\u202a-\u202e\u2066-\u2069]")  # what must not reach a terminal


@dataclass
class Case:
    """One reproducer: its class (the issue's item), the command's arguments, the files made first (name -> text,
    bytes, or a callable that makes it at the path), the exit codes it may end with, and the files it says it
    writes (changes to those are its to make)."""

    item: str
    name: str
    args: list[str]
    files: dict = field(default_factory=dict)
    exits: tuple[int, ...] = (2,)
    writes: tuple[str, ...] = ()
    check: object = None  # (folder, output) -> a problem's text or None: what else the case must show
    stdin: str = ""


def fifo(path: Path) -> None:
    os.mkfifo(path)


def unix_socket(path: Path) -> None:
    sock = socket.socket(socket.AF_UNIX)
    sock.bind(str(path))  # left bound: the file stays a socket for the case's run


def symlink_to(target: str):
    def make(path: Path) -> None:
        path.symlink_to(target)

    return make


def read_only(text: str):
    def make(path: Path) -> None:
        path.write_text(text, encoding="utf-8")
        path.chmod(0o444)

    return make


def hard_linked(text: str):
    def make(path: Path) -> None:
        path.write_text(text, encoding="utf-8")
        os.link(path, path.with_name(path.name + ".link"))

    return make


def ur(*lines: str) -> str:
    return "def prog():\n" + "".join(f"  {line}\n" for line in lines) + "end\n"


def krl(decls: str, *lines: str) -> str:
    return f"DEF prog()\n{decls}\n" + "".join(f"{line}\n" for line in lines) + "END\n"


def rapid(data: str, *lines: str) -> str:
    return f"MODULE m\n{data}\nPROC main()\n" + "".join(f"{line}\n" for line in lines) + "ENDPROC\nENDMODULE\n"


def pallet_cell(old: str, new: str, name: str = "cell.toml") -> dict:
    assert old in TESTMAT, old
    return {name: TESTMAT.replace(old, new, 1)}


def says(words: str, absent: bool = False):
    def check(_folder: Path, output: str) -> str | None:
        if (words in output) == absent:
            return f"{'says' if absent else 'does not say'} {words!r}"
        return None

    return check


def crlf_kept(name: str):
    def check(folder: Path, _output: str) -> str | None:
        data = (folder / name).read_bytes()
        return None if data.count(b"\n") == data.count(b"\r\n") else "its CRLF line ends were not kept"

    return check


HANDEYE_DEGENERATE = "u,v,x,y\n" + "".join(
    f"{100 + i * 1e-9:.12f},{100 + j * 1e-9:.12f},{10 + i},{10 + j}\n" for i in range(3) for j in range(3)
)
TOUCHES = (EXAMPLES / "conveyor_touches.csv").read_text(encoding="utf-8").splitlines()
REVERSED = (
    "\n".join(
        [
            TOUCHES[0],
            *reversed([t for t in TOUCHES[1:] if t.endswith("belt")]),
            *[t for t in TOUCHES[1:] if not t.endswith("belt")],
        ]
    )
    + "\n"
)
ESC = "\x1b[2J\x1b]0;owned\x07\u202e"


def cases() -> list[Case]:
    big = "# " + "x" * 78 + "\n"
    out = [
        # 1. program files read like cell files
        Case("1 program file", "run a FIFO", ["run", "p.script"], {"p.script": fifo}),
        Case("1 program file", "check a FIFO", ["check", "p.script", "--target", "ur"], {"p.script": fifo}),
        Case("1 program file", "run /dev/zero", ["run", "/dev/zero", "--target", "ur"]),
        Case("1 program file", "check /dev/urandom", ["check", "/dev/urandom", "--target", "kuka"]),
        Case("1 program file", "run a socket", ["run", "p.script"], {"p.script": unix_socket}),
        Case(
            "1 program file",
            "run a folder",
            ["run", "d.script", "--target", "ur"],
            {"d.script/x.script": ur("x = 1")},
            (0, 2),
        ),
        Case("1 program file", "run 17 MiB", ["run", "p.script"], {"p.script": big * (17 * 2**20 // len(big))}),
        Case(
            "1 program file",
            "check a 20,000-character line",
            ["check", "p.script"],
            {"p.script": ur("x = " + "+".join(["1"] * 10_000))},
        ),
        Case("1 program file", "run binary bytes", ["run", "p.src"], {"p.src": bytes(range(256)) * 64}),
        Case(
            "1 program file", "KRL DECL INT A[1000000000]", ["run", "p.src"], {"p.src": krl("DECL INT A[1000000000]")}
        ),
        Case(
            "1 program file",
            "RAPID a{100000,100000}",
            ["check", "p.mod"],
            {"p.mod": rapid("VAR num a{100000,100000};", "a{1,1} := 1;")},
        ),
        Case("1 program file", "dtrans Int a[100000000]", ["run", "p.prg"], {"p.prg": "Int a[100000000]\na[0] = 1\n"}),
        Case(
            "1 program file",
            "--step-limit 1e12",
            ["run", "p.script", "--step-limit", "1000000000000"],
            {"p.script": ur("x = 1")},
        ),
        Case("1 program file", "run a runaway loop", ["run", "p.script"], {"p.script": ur("while True:", "end")}, (1,)),
        Case(
            "1 program file",
            "check a runaway loop",
            ["check", "p.script"],
            {"p.script": ur("while True:", "end")},
            check=says("runaway-loop"),
        ),
        Case(
            "1 program file",
            "URScript int past 32 bits",
            ["run", "p.script"],
            {"p.script": ur("x = 2147483647", "x = -(-x - 1)", "textmsg(x)")},
            (1,),
        ),
        Case(
            "1 program file",
            "URScript to_num past 32 bits",
            ["run", "p.script"],
            {"p.script": ur('x = to_num("99999999999")', "textmsg(x)")},
            (1,),
        ),
        # 2. output files
        Case(
            "2 output file", "schema --out the user's cell", ["schema", "--out", "mycell.toml"], {"mycell.toml": BENCH}
        ),
        Case("2 output file", "schema --out a FIFO", ["schema", "--out", "s.json"], {"s.json": fifo}),
        Case("2 output file", "schema --out /dev/null", ["schema", "--out", "/dev/null"]),
        Case(
            "2 output file",
            "schema --out a link to the user's file",
            ["schema", "--out", "s.json"],
            {"mine.txt": "mine\n", "s.json": symlink_to("mine.txt")},
        ),
        Case("2 output file", "schema --out a name of 300 bytes", ["schema", "--out", "n" * 300 + ".json"]),
        Case(
            "2 output file",
            "schema --out a read-only schema",
            ["schema", "--out", "s.json"],
            {"s.json": read_only('{"title": "codegen cell file"}\n')},
        ),
        Case(
            "2 output file",
            "view --out a FIFO",
            ["view", "cell.toml", "--out", "v.html"],
            {"cell.toml": BENCH, "v.html": fifo},
        ),
        Case(
            "2 output file",
            "view --out the user's page",
            ["view", "cell.toml", "--out", "v.html"],
            {"cell.toml": BENCH, "v.html": "<html>mine</html>\n"},
        ),
        Case(
            "2 output file",
            "verify --html the user's page",
            ["verify", "cell.toml", "--html", "v.html"],
            {"cell.toml": BENCH, "v.html": "<html>mine</html>\n"},
        ),
        Case(
            "2 output file",
            "verify --timings the user's file",
            ["verify", str(EXAMPLES / "plant"), "--timings", "t.json"],
            {"t.json": '{"mine": 1}\n'},
        ),
        Case(
            "2 output file",
            "pallet --svg over the user's picture",
            ["pallet", "--svg", "svg"],
            {"svg/testmat_layer02.svg": "<svg>mine</svg>\n"},
        ),
        # 3. calibrations that write the cell
        Case(
            "3 calibration",
            "handeye --write a hard-linked cell",
            ["calibrate", "handeye", "p.csv", "--write", "cell.toml"],
            {"p.csv": (EXAMPLES / "thermometer_bench_points.csv").read_text(), "cell.toml": hard_linked(BENCH)},
        ),
        Case(
            "3 calibration",
            "handeye --write a read-only cell",
            ["calibrate", "handeye", "p.csv", "--write", "cell.toml"],
            {"p.csv": (EXAMPLES / "thermometer_bench_points.csv").read_text(), "cell.toml": read_only(BENCH)},
        ),
        Case(
            "3 calibration",
            "handeye --write a CRLF cell",
            ["calibrate", "handeye", "p.csv", "--write", "cell.toml"],
            {
                "p.csv": (EXAMPLES / "thermometer_bench_points.csv").read_text(),
                "cell.toml": BENCH.replace("\n", "\r\n").encode(),
            },
            (0,),
            ("cell.toml",),
            crlf_kept("cell.toml"),
        ),
        # 4. cells generate accepts are cells verify passes (here: refused with the key named, or generated)
        Case(
            "4 cell",
            "done on the gripper's output",
            ["generate", "cell.toml", "--target", "ur", "--out", "o"],
            pallet_cell("done = { ur = 2,", "done = { ur = 0,"),
            writes=("o",),
        ),
        Case(
            "4 cell",
            "part_present = pallet_present",
            ["generate", "cell.toml", "--target", "ur", "--out", "o"],
            pallet_cell("part_present = { ur = 2,", "part_present = { ur = 3,"),
            writes=("o",),
        ),
        Case(
            "4 cell",
            "a box heavier than the arm's payload",
            ["generate", "cell.toml", "--target", "kuka", "--out", "o"],
            pallet_cell("box_mass_kg = 0.05", "box_mass_kg = 50.0"),
            writes=("o",),
        ),
        Case(
            "4 cell",
            "the pick inside the pallet's footprint",
            ["generate", "cell.toml", "--target", "kuka", "--out", "o"],
            pallet_cell("pick = [600.0, 300.0, 50.0,", "pick = [700.0, -10.0, 50.0,"),
            writes=("o",),
        ),
        Case(
            "4 cell",
            "a pallet name of 60 characters",
            ["generate", "cell.toml", "--target", "kuka", "--out", "o"],
            pallet_cell('name = "testmat"', 'name = "' + "t" * 60 + '"'),
            (0, 2),
            ("o",),
        ),
        Case(
            "4 cell",
            "home at a joint limit",
            ["generate", "cell.toml", "--target", "kuka", "--out", "o"],
            pallet_cell(
                'abb = "IRB 1200-5/0.9"\n',
                'abb = "IRB 1200-5/0.9"\nhome = { kuka = [170.0, -90.0, 90.0, 0.0, 90.0, 0.0] }\n',
            ),
            writes=("o",),
        ),
        Case(
            "4 cell",
            "max_shift_mm = 1e9",
            ["generate", "cell.toml", "--out", "o"],
            {"cell.toml": BENCH.replace("max_shift_mm = 80.0", "max_shift_mm = 1e9")},
            writes=("o",),
        ),
        Case(
            "4 cell",
            "a refinement that cannot converge",
            ["generate", "cell.toml", "--out", "o"],
            {"cell.toml": BENCH.replace("tolerance_mm = 0.02", "tolerance_mm = 1e-12")},
            (0, 2),
            ("o",),
        ),
        Case("4 cell", "a cell file that is a FIFO", ["generate", "cell.toml", "--out", "o"], {"cell.toml": fifo}),
        Case("4 cell", "a cell file that is /dev/zero", ["generate", "/dev/zero", "--out", "o"]),
        Case(
            "4 cell",
            "a cell named ../other/victim",
            ["view", "cell.toml"],
            {
                "cell.toml": BENCH.replace('name = "thermometer_bench"', 'name = "../other/victim"'),
                "../other/victim.html": "<html>mine</html>\n",
            },
            (0, 2),
            ("*.html",),
        ),
        # 5. values as the controllers hold them
        Case("5 value", "URScript 1e999", ["run", "p.script"], {"p.script": ur("x = 1e999")}),
        Case("5 value", "URScript a 5000-digit number", ["check", "p.script"], {"p.script": ur("x = " + "9" * 5000)}),
        Case(
            "5 value",
            "real overflow at run time",
            ["run", "p.mod"],
            {"p.mod": rapid("VAR num x := 1E30;", "x := x * x * x;")},
            (1,),
        ),
        Case(
            "5 value",
            "KRL CHAR S[10] given 11",
            ["run", "p.src"],
            {"p.src": krl("DECL CHAR S[10]", 'S[] = "01234567890"')},
        ),
        Case("5 value", "RAPID a{2.5} declared", ["run", "p.mod"], {"p.mod": rapid("VAR num a{2.5};", "a{1} := 1;")}),
        Case("5 value", "RAPID a{0} declared", ["check", "p.mod"], {"p.mod": rapid("VAR num a{0};")}),
        Case(
            "5 value",
            "RAPID a{1.5} read",
            ["run", "p.mod"],
            {"p.mod": rapid("VAR num a{3};\nVAR num k := 1.5;", "a{k} := 1;")},
            (1,),
        ),
        Case("5 value", "RAPID a{1.5} in check", ["check", "p.mod"], {"p.mod": rapid("VAR num a{3};", "a{1.5} := 1;")}),
        Case("5 value", "a duplicated DECL", ["check", "p.src"], {"p.src": krl("DECL INT N\nDECL REAL N", "N = 1")}),
        Case(
            "5 value",
            "KRL WAIT SEC -5",
            ["run", "p.src"],
            {"p.src": krl("", "WAIT SEC -5")},
            (0,),
            check=says("does not wait"),
        ),
        Case("5 value", "--input x=nan", ["run", "p.script", "--input", "x=nan"], {"p.script": ur("textmsg(x)")}),
        Case(
            "5 value",
            "--start 1e308",
            ["run", "p.script", "--start", "1e308,0,0,0,0,0"],
            {"p.script": ur("textmsg(1)")},
        ),
        Case(
            "5 value",
            "--signal standard_digital_in[99]",
            ["run", "p.script", "--signal", "standard_digital_in[99]=1"],
            {"p.script": ur("textmsg(1)")},
        ),
        Case(
            "5 value", "handeye points 1e-9 px apart", ["calibrate", "handeye", "p.csv"], {"p.csv": HANDEYE_DEGENERATE}
        ),
        Case(
            "5 value",
            "reversed conveyor touches",
            ["calibrate", "conveyor", "t.csv", "--counter-bits", "16", "--write", "cell.toml"],
            {"t.csv": REVERSED, "cell.toml": (EXAMPLES / "conveyor" / "belt_pick.toml").read_text(encoding="utf-8")},
            check=says("reversed"),
        ),
        Case(
            "5 value",
            "check an 81-character RAPID string",
            ["check", "p.mod"],
            {"p.mod": rapid("VAR string s;", 's := "' + "a" * 41 + '" + "' + "b" * 40 + '";')},
        ),
        Case(
            "5 value", "check a KRL division by 'H0'", ["check", "p.src"], {"p.src": krl("DECL INT X", "X = 1 / 'H0'")}
        ),
        # 6. the terminal is inert
        Case(
            "6 terminal",
            "a program's message with escapes",
            ["run", "p.script"],
            {"p.script": ur(f'textmsg("{ESC}")')},
            (0,),
        ),
        Case(
            "6 terminal",
            "a program's error at a name with escapes",
            ["run", "p.script"],
            {"p.script": ur(f"x = {ESC[0]}y")},
        ),
        Case(
            "6 terminal",
            "a cell's name with escapes",
            ["generate", "cell.toml", "--target", "ur", "--out", "o"],
            {"cell.toml": BENCH.replace('name = "bath"', f'name = "ba{ESC}th"')},
            (0, 2),
            ("o",),
        ),
        Case(
            "6 terminal",
            "a file name with escapes",
            ["check", f"p{ESC[:4]}.script"],
            {f"p{ESC[:4]}.script": ur("x = ")},
        ),
        # 7. messages
        Case(
            "7 message",
            "conveyor = 5",
            ["generate", "cell.toml", "--out", "o"],
            {"cell.toml": "conveyor = 5\n" + BENCH},
            check=says("cell.camera: missing", absent=True),
        ),
    ]
    return out


def snapshot(folder: Path) -> dict[str, str]:
    """Every entry under the folder (and its sibling `other`): kind and content hash (a FIFO or socket by kind)."""
    out = {}
    for base in (folder, folder.parent / "other"):
        for path in sorted(base.rglob("*")) if base.exists() else []:
            key = os.path.relpath(path, folder)
            if path.is_symlink():
                out[key] = "link " + os.readlink(path)
            elif path.is_file():
                out[key] = hashlib.sha256(path.read_bytes()).hexdigest() + f" {oct(path.stat().st_mode & 0o777)}"
            elif path.is_dir():
                out[key] = "dir"
            else:
                out[key] = "special"
    return out


def make(folder: Path, files: dict) -> None:
    for name, content in files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if callable(content):
            content(path)
        elif isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content, encoding="utf-8")


def allowed(key: str, writes: tuple[str, ...]) -> bool:
    """A change the command says it makes: under a file or folder it names, in the case's own folder."""
    return not key.startswith("..") and any(
        key == w or key.startswith(w + os.sep) or Path(key).match(w) for w in writes
    )


def run(case: Case, folder: Path, timeout: float) -> dict:
    """One case: its outcome (exit, seconds, output) and the problems found."""
    make(folder, case.files)
    before = snapshot(folder)
    start = time.perf_counter()
    command = [sys.executable, "-m", "codegen", *case.args]
    env = {**os.environ, "COLUMNS": "120", "NO_COLOR": "1"}
    process = subprocess.Popen(
        command,
        cwd=folder,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        stdin=subprocess.DEVNULL,
        env=env,
        start_new_session=True,
    )
    try:
        raw, _ = process.communicate(timeout=timeout)
        code = process.returncode
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)  # the case's own process group: its command and what it started
        raw, _ = process.communicate()
        code = None
    seconds = time.perf_counter() - start
    output = raw.decode("utf-8", "replace")
    problems = []
    if code is None:
        problems.append(f"hang (killed after {timeout:g} s)")
    elif code not in case.exits:
        problems.append(f"exit {code}, expected {' or '.join(map(str, case.exits))}")
    if "Traceback (most recent call last)" in output:
        problems.append("traceback")
    if TERMINAL.search(output.replace("\r\n", "\n")):
        problems.append("a control character or bidirectional override in the output")
    after = snapshot(folder)
    changed = sorted(
        k for k in set(before) | set(after) if before.get(k) != after.get(k) and not allowed(k, case.writes)
    )
    if changed:
        problems.append("user files changed: " + ", ".join(changed[:4]))
    if case.check is not None and code is not None:
        said = case.check(folder, output)
        if said:
            problems.append(said)
    return {"exit": code, "seconds": seconds, "output": output, "problems": problems}


def concurrent_calibrations(root: Path, timeout: float) -> tuple[str, list[str]]:
    """handeye --write and tcp --write on one cell at the same moment: both results must be in the cell after."""
    folder = root / "concurrent"
    make(
        folder,
        {
            "cell.toml": BENCH,
            "p.csv": (EXAMPLES / "thermometer_bench_points.csv").read_text(),
            "t.csv": (EXAMPLES / "agv_gripper_touches.csv").read_text(),
        },
    )
    commands = [
        ["calibrate", "handeye", "p.csv", "--write", "cell.toml"],
        ["calibrate", "tcp", "t.csv", "--write", "cell.toml"],
    ]
    runs = [
        subprocess.Popen(
            [sys.executable, "-m", "codegen", *c],
            cwd=folder,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            start_new_session=True,
        )
        for c in commands
    ]
    problems, outputs = [], []
    for process in runs:
        try:
            raw, _ = process.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            raw, _ = process.communicate()
            problems.append("hang")
        outputs.append(raw.decode("utf-8", "replace"))
        if "Traceback" in outputs[-1]:
            problems.append("traceback")
    text = (folder / "cell.toml").read_text(encoding="utf-8")
    if "written by `codegen calibrate handeye`" in BENCH and text.count("[cell.camera.handeye]") != 1:
        problems.append("the hand-eye table lost or doubled")
    if "tcp = [0.0, 0.0, 150.0, 0.0, 0.0, 0.0]" in text and all("wrote" in o for o in outputs):
        problems.append("both said they wrote, the tcp was lost")
    return "3 calibration: handeye and tcp --write at once", problems


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", default="", help="only the cases whose item or name holds this word")
    parser.add_argument("--timeout", type=float, default=90.0, help="seconds before a case is a hang")
    options = parser.parse_args()
    chosen = [c for c in cases() if options.only.lower() in f"{c.item} {c.name}".lower()]
    counts = {"cases": 0, "traceback": 0, "hang": 0, "exit": 0, "files": 0, "terminal": 0, "other": 0}
    root = Path(tempfile.mkdtemp(prefix="codegen-probe-"))
    flagged = []
    try:
        for i, case in enumerate(chosen):
            folder = root / f"case{i:03d}" / "work"
            folder.mkdir(parents=True)
            result = run(case, folder, options.timeout)
            counts["cases"] += 1
            for problem in result["problems"]:
                key = next(
                    (
                        k
                        for k, w in (
                            ("traceback", "traceback"),
                            ("hang", "hang"),
                            ("exit", "exit "),
                            ("files", "user files"),
                            ("terminal", "a control character"),
                        )
                        if problem.startswith(w)
                    ),
                    "other",
                )
                counts[key] += 1
            mark = "ok " if not result["problems"] else "BAD"
            shown = "-" if result["exit"] is None else result["exit"]
            print(
                f"{mark} {case.item:<16} {case.name:<45} exit {shown:<3} {result['seconds']:6.1f} s  "
                + "; ".join(result["problems"]),
                flush=True,
            )
            if result["problems"]:
                flagged.append((case, result))
        if not options.only or options.only.lower() in "3 calibration concurrent":
            name, problems = concurrent_calibrations(root, options.timeout)
            counts["cases"] += 1
            counts["other"] += len(problems)
            print(f"{'ok ' if not problems else 'BAD'} {name}  " + "; ".join(problems), flush=True)
    finally:
        for path in root.rglob("*"):  # read-only files and folders made by the cases: removable again
            if not path.is_symlink():
                path.chmod(0o755 if path.is_dir() else 0o644)
        shutil.rmtree(root, ignore_errors=True)
    print(
        f"\n{counts['cases']} cases: {counts['traceback']} tracebacks, {counts['hang']} hangs, {counts['exit']} "
        f"unexpected exit codes, {counts['files']} with user files changed, {counts['terminal']} with control "
        f"characters in the output, {counts['other']} other problems"
    )
    for case, result in flagged:
        tail = result["output"].strip().splitlines()[-3:]
        print(f"\n--- {case.name}: {'; '.join(result['problems'])}\n    " + "\n    ".join(t[:200] for t in tail))
    return 1 if flagged else 0


if __name__ == "__main__":
    sys.exit(main())
