"""verify's report as a page: a table per target and section, the errors' distributions, the arm's margins, the
mismatches, and the worst cases replayed in the cell's 3D view beside the reference's poses."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from markupsafe import Markup, escape

from codegen.verify.programs import fresh_sources
from codegen.view.page import page_data, program_json, render, view_json
from codegen.view.runs import ProgramRuns, Run

PLOT_W, PLOT_H, PAD = 460, 190, 38  # an error plot's size and its margin for the axes (px)
BINS_PER_DECADE = 4
SERIES = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf")


def _texts(cell, row) -> list[tuple[str, str]]:
    """The row's program files with their text (fresh: rendered again; given: read), for the page's source lines."""
    if row.files and row.files[0].startswith("<fresh>"):
        for source in fresh_sources(cell, [row.target]):
            if source.kind == row.kind and source.ident == row.program:
                return [(Path(f.name).name, f.text) for f in source.files]
        return []
    out = []
    for name in row.files[:1]:
        try:
            out.append((Path(name).name, Path(name).read_text(encoding="utf-8", errors="replace")))
        except OSError:
            out.append((Path(name).name, ""))
    return out


def replays(cell, row) -> list[dict]:
    """The row's kept cases as the page's programs: the worst passing case and a mismatching one, each with the
    reference's poses."""
    out = []
    files = None
    for title, replay in (("worst case", row.worst), ("mismatch", row.failed)):
        if replay is None or replay.trace is None:
            continue
        files = files if files is not None else _texts(cell, row)
        run = Run(replay.what, replay.start_joints, replay.trace, replay.reference)
        entry = ProgramRuns(row.target, row.program, row.kind, files or [("", "")], [run], replay.problem)
        errors = f"position {replay.pos_max:.2e} mm, rotation {replay.rot_max:.2e} deg"
        label = f"{row.program}: {title} ({'mismatch' if replay.problem else errors})"
        out.append(program_json(entry, label))
    return out


def histogram(values) -> tuple[list[float], list[int], int]:
    """Counts per bin of log10(value), BINS_PER_DECADE per decade (edges), and how many values are exactly 0."""
    arr = np.frombuffer(values, dtype=float) if values else np.zeros(0)
    zeros = int(np.count_nonzero(arr == 0.0))
    positive = arr[arr > 0.0]
    if not positive.size:
        return [], [], zeros
    logs = np.log10(positive)
    low, high = math.floor(logs.min()), math.ceil(logs.max() + 1e-12)
    edges = np.linspace(low, high, int(high - low) * BINS_PER_DECADE + 1)
    counts, _ = np.histogram(logs, bins=edges)
    return [float(e) for e in edges], [int(c) for c in counts], zeros


def plot(rows, attribute: str, unit: str) -> Markup:
    """An SVG: for each program the distribution of its errors (a step line over log-spaced bins)."""
    series = [(row.program, histogram(getattr(row, attribute))) for row in rows]
    edges = [e for _, (es, _, _) in series for e in es]
    if not edges:
        return Markup(f"<p>no {escape(unit)} errors compared</p>")
    low, high = min(edges), max(edges)
    top = max(max(cs) for _, (_, cs, _) in series if cs) or 1
    width, height = PLOT_W - 2 * PAD, PLOT_H - 2 * PAD

    def x(v: float) -> float:
        return PAD + (v - low) / max(high - low, 1e-9) * width

    def y(c: float) -> float:
        return PAD + height - c / top * height

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{PLOT_W}" height="{PLOT_H}" class="plot">']
    parts.append(f'<rect x="{PAD}" y="{PAD}" width="{width}" height="{height}" fill="none" stroke="#999"/>')
    step = max(1, math.ceil((high - low) / 8))  # at most about 8 labelled decades
    for decade in range(math.ceil(low), math.floor(high) + 1, step):
        parts.append(
            f'<line x1="{x(decade):.1f}" y1="{PAD + height}" x2="{x(decade):.1f}" y2="{PAD + height + 4}" '
            'stroke="#666"/>'
        )
        parts.append(
            f'<text x="{x(decade):.1f}" y="{PAD + height + 16}" font-size="11" text-anchor="middle">1e{decade}</text>'
        )
    parts.append(
        f'<text x="{PAD}" y="{PAD - 8}" font-size="12">{escape(unit)} error per compared move (count, log '
        f"bins; top {top})</text>"
    )
    for i, (name, (es, cs, zeros)) in enumerate(series):
        colour = SERIES[i % len(SERIES)]
        if cs:
            points = [(x(es[0]), y(0))]
            for k, count in enumerate(cs):
                points += [(x(es[k]), y(count)), (x(es[k + 1]), y(count))]
            points.append((x(es[-1]), y(0)))
            text = " ".join(f"{px:.1f},{py:.1f}" for px, py in points)
            parts.append(f'<polyline points="{text}" fill="none" stroke="{colour}" stroke-width="1.5"/>')
        label = f"{name}" + (f" ({zeros} exactly 0)" if zeros else "")
        parts.append(
            f'<text x="{PAD + width - 4}" y="{PAD + 14 + 13 * i}" font-size="11" text-anchor="end" '
            f'fill="{colour}">{escape(label)}</text>'
        )
    parts.append("</svg>")
    return Markup("".join(parts))


def target_table(rows) -> list[dict]:
    """The rows of one target in the kinds' order (each kind a section), with the figures the table shows."""
    out = []
    for row in sorted(rows, key=lambda r: (r.plan.kind.order, r.kind)):
        s = row.summary()
        arm = s.get("arm")
        out.append(
            {
                "kind": row.kind,
                "program": row.program,
                "files": ", ".join(row.files),
                "cases": s["cases"],
                "mismatches": s["mismatches"],
                "halts": s["halts"],
                "boundary": s["boundary_cases"],
                "moves": s["moves_compared"],
                "pos_max": f"{s['position_error_mm']['max']:.2e}",
                "pos_p99": f"{s['position_error_mm']['p99']:.2e}",
                "rot_max": f"{s['orientation_error_deg']['max']:.2e}",
                "rot_p99": f"{s['orientation_error_deg']['p99']:.2e}",
                "joint_margin": "" if arm is None else f"{arm['joint_margin_deg']:.1f}",
                "wrist_margin": "" if arm is None else f"{arm['wrist_margin_deg']:.1f}",
                "clearance": "" if row.clearance is None else f"{row.clearance.distance:.1f}",
                "clearance_where": "" if row.clearance is None else (
                    f"{row.clearance.body} - {row.clearance.other} at {row.clearance.where}, the {row.clearance.what} "
                    f"({row.clearance_traces} traces swept)"),
                "first_mismatches": row.first_mismatches,
                "more": row.mismatches - len(row.first_mismatches),
            }
        )
    return out


def report_page(cell, report) -> str:
    """The page of a verify report whose rows kept their replays (Options.keep_replays)."""
    targets = list(dict.fromkeys(row.target for row in report.rows))
    sections, views = [], []
    for target in targets:
        rows = [r for r in report.rows if r.target == target]
        sections.append(
            {
                "target": target,
                "rows": target_table(rows),
                "position": plot(rows, "pos_errors", "position (mm)"),
                "rotation": plot(rows, "rot_errors", "rotation (deg)"),
            }
        )
        programs = [p for row in rows for p in replays(cell, row)]
        if programs:
            views.append(view_json(cell, target, programs))
    return render(
        "report.html.j2",
        f"codegen verify: cell {cell.name}",
        page_data(cell, views),
        report=report,
        sections=sections,
        runs=sum(r.cases for r in report.rows),
    )
