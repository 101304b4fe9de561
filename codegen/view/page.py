"""A cell's page: its objects, each target's arm and the nominal runs' traces as JSON in one self-contained file."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from markupsafe import Markup

from codegen import __version__, data_dir
from codegen.robot.expect import arm_of
from codegen.verify import clearance
from codegen.view.objects import cell_objects
from codegen.view.runs import ProgramRuns, Run, nominal_runs
from codegen.view.scene import arm_description, flat
from codegen.writefile import check_own, write_own

TOUCH_MM = 2.0  # the TCP this near a box's top centre is on it (where a stacking plan puts the TCP)
GENERATOR = "codegen view"  # the page's <meta name="generator">: a file that has it is one codegen may replace
STATIC = Path(__file__).with_name("static")
# the page's own script, one file per job, inlined in this order into one element: the arm's forward kinematics,
# numbers rounded for reading, the labels' placing on the screen, the runs' timeline, then the viewer (the scene,
# the panel, the controls) that uses them
VIEWER = ("kinematics.js", "numbers.js", "labels.js", "timeline.js", "viewer.js")
TEMPLATES = data_dir("templates") / "view"
NOTE = (
    "The arm is drawn from its catalogue kinematics at the joints the interpreter solved for each move (between two "
    "moves at joints interpolated linearly); the path joins the poses the trace records."
)


def run_json(run: Run) -> dict:
    """A run as the page has it: the trace's moves (kind, line, program clock, joints as solved, pose), outputs,
    the stop, and the reference's poses where given."""
    moves = [
        {
            "kind": m.kind,
            "line": m.line,
            "t": round(float(m.end_time), 6),
            "joints": None if m.joints is None else [float(v) for v in m.joints],
            "pose": None if m.tcp2base is None else flat(m.tcp2base),
        }
        for m in run.trace.moves
    ]
    outputs = [{"name": o.name, "value": o.value, "after": o.after_moves} for o in run.trace.outputs]
    out = {
        "what": run.what,
        "start": None if run.start_joints is None else [float(v) for v in run.start_joints],
        "moves": moves,
        "outputs": outputs,
        "halt": run.trace.halt_message if run.trace.halted else None,
    }
    if run.reference is not None:
        out["reference"] = [None if p is None else flat(p) for p in run.reference]
    return out


def program_json(entry: ProgramRuns, label: str | None = None) -> dict:
    """A program's runs, its program file's name and the text of the lines its moves name."""
    name, text = entry.files[0] if entry.files else ("", "")
    lines = text.splitlines()
    used = sorted({m.line for run in entry.runs for m in run.trace.moves if 0 < m.line <= len(lines)})
    return {
        "label": label or f"{entry.program} ({entry.kind})",
        "program": entry.program,
        "kind": entry.kind,
        "file": name,
        "source": {str(n): lines[n - 1] for n in used},
        "runs": [run_json(r) for r in entry.runs],
        "problem": entry.problem,
    }


def with_clearance(cell, target: str, entry: ProgramRuns, program: dict) -> dict:
    """The program's runs each with its least clearance among the cell's solids (verify's sweep of every move): the
    move (its index), the distance, the bodies and what the move is; none where the cell gives no arm shapes."""
    check = clearance.for_program(cell, target, program["file"])
    if check is None:
        return program
    for run, shown in zip(entry.runs, program["runs"], strict=True):
        least, _ = check.check(run.trace, run.start_joints)
        if least is not None:
            shown["clearance"] = {"move": least.move, "distance": round(float(least.distance), 1), "body": least.body,
                                  "other": least.other, "what": least.what, "clearance": check.clearance}
    return program


def view_json(cell, target: str, programs: list[dict]) -> dict:
    """One target's view: its arm (None: poses alone) and its programs."""
    arm = arm_of(cell, target)
    tool = cell.robot.tool.tcp2flange if cell.robot is not None else np.eye(4)
    label = f"{target}: {arm.model}" if arm is not None else f"{target}: no arm model (poses alone)"
    return {
        "target": target,
        "label": label,
        "arm": None if arm is None else arm_description(arm, tool),
        "programs": programs,
    }


def cell_data(cell, targets: list[str]) -> dict:
    """The page's data: the cell's objects and, per target, the nominal run of each program."""
    views = [view_json(cell, t, [with_clearance(cell, t, p, program_json(p)) for p in nominal_runs(cell, t)])
             for t in targets]
    return page_data(cell, views)


def page_data(cell, views: list[dict]) -> dict:
    """The cell's objects and the views, each run with the boxes it places or takes (mark_boxes)."""
    objects = cell_objects(cell)
    for view in views:
        for program in view["programs"]:
            for run in program["runs"]:
                run["boxes"] = mark_boxes(objects, run)
    return {"generator": GENERATOR, "cell": cell.name, "objects": objects, "views": views}


def mark_boxes(objects: list[dict], run: dict) -> list[list[int]]:
    """The boxes a run places or takes: [object index, the move whose end puts the TCP on the box's top centre first
    (within TOUCH_MM), 1 where the run places boxes (it reaches the lower ones first: the box is there from that move
    on), 0 where it takes them (the box is there up to that move)]. The page draws a box that is not there as a
    ghost; a box the run never reaches stays as the cell has it. A box's label goes with its box; a slip sheet lies
    on its layer once the layer's last box is placed, and is gone before the layer's first box is taken."""
    boxes = [i for i, o in enumerate(objects) if o["type"] == "box" and o["role"] == "box"]
    poses = [(k, m["pose"]) for k, m in enumerate(run["moves"]) if m["pose"] is not None]
    if not boxes or not poses:
        return []
    tops = np.array([_top(objects[i]) for i in boxes])
    tcp = np.array([pose[3:12:4] for _k, pose in poses])
    near = np.linalg.norm(tops[:, None, :] - tcp[None, :, :], axis=2) <= TOUCH_MM
    touched = [(i, poses[int(np.argmax(row))][0], top[2]) for i, row, top in zip(boxes, near, tops, strict=True)]
    touched = sorted((t for t, row in zip(touched, near, strict=True) if row.any()), key=lambda t: t[1])
    if not touched:
        return []
    placing = int(touched[0][2] <= touched[-1][2])
    out = [[i, k, placing] for i, k, _z in touched]
    out += [[i + 1, k, placing] for i, k, _z in touched if i + 1 < len(objects) and objects[i + 1]["role"] == "label"]
    for index, sheet in enumerate(objects):
        if sheet["role"] == "sheet":
            below = [k for i, k, _z in touched if _under(sheet, _top(objects[i]))]
            if below:
                out.append([index, max(below), 1] if placing else [index, min(below) - 1, 0])
    return out


def _under(sheet: dict, point: np.ndarray) -> bool:
    """Whether a box's top centre lies under the sheet (within its outline, its top at the sheet's bottom)."""
    pose = np.reshape(sheet["pose"], (4, 4))
    local = pose[:3, :3].T @ (point - pose[:3, 3])
    length, width, height = sheet["size"]
    return abs(local[0]) <= length / 2 and abs(local[1]) <= width / 2 and abs(local[2] + height / 2) <= TOUCH_MM


def _top(box: dict) -> np.ndarray:
    pose = np.reshape(box["pose"], (4, 4))
    return pose[:3, 3] + pose[:3, 2] * box["size"][2] / 2


def embedded_json(data: dict) -> str:
    """JSON safe inside a <script> element: no '<' (so no '</script>' or '<!--'), whatever the cell's strings hold."""
    return json.dumps(data, separators=(",", ":"), allow_nan=False).replace("<", "\\u003c")


def _script(name: str) -> str:
    text = (STATIC / name).read_text(encoding="utf-8")
    if "</script" in text.lower():  # the page inlines it: it must not end its own element
        raise RuntimeError(f"{name} holds '</script'")
    return text


def render(template: str, title: str, data: dict, **context) -> str:
    """The page from templates/view/<template> with the viewer, three.js and the data inlined (works offline)."""
    import jinja2  # imported where used, as codegen.render does

    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(TEMPLATES)),
        undefined=jinja2.StrictUndefined,
        autoescape=True,
        trim_blocks=True,
        lstrip_blocks=True,
    )
    return env.get_template(template).render(
        generator=f"{GENERATOR} {__version__}",
        title=title,
        note=NOTE,
        css=Markup(_script("viewer.css")),
        three=Markup(_script("three.min.js")),
        viewer=Markup("\n".join(_script(name) for name in VIEWER)),
        data=Markup(embedded_json(data)),
        **context,
    )


def cell_page(cell, targets: list[str]) -> str:
    return render("cell.html.j2", f"codegen view: cell {cell.name}", cell_data(cell, targets))


MARKS = (f'<meta name="generator" content="{GENERATOR}'.encode(),)  # in a page's first lines: one codegen wrote


def check_out(path: Path) -> None:
    """WriteRefused unless a page may be written there (codegen.writefile.check_own: a file codegen did not write,
    a folder, a FIFO or a device is left alone)."""
    check_own(path, MARKS)


def write_page(path: Path, html: str) -> None:
    """Write the page whole (codegen.writefile.write_own); a file there that codegen did not write is left alone."""
    write_own(path, html, MARKS)
