"""`codegen correct`: the reference result for one reading in every target's native pose format."""

from __future__ import annotations

from codegen.controllers import get_target
from codegen.decimals import format_literal
from codegen.guard import halt_message
from codegen.kinds.station.point.reference import Reading, expected_trace
from codegen.kinds.station.section import section_of
from codegen.model.cell import Cell
from codegen.poses import POSE_FORMATS, pose_text, shown_values


def correct_report(cell: Cell, reading: Reading) -> dict:
    trace = expected_trace(cell, reading)
    detail = trace.detail
    report: dict = {
        "cell": cell.name,
        "reading": {"station_id": reading.station_id, "x_mm": reading.x, "y_mm": reading.y, "theta_deg": reading.theta},
        "angle_sign": section_of(cell).angle_sign,
        "station": None
        if trace.station is None
        else {"id": trace.station.id, "name": trace.station.name, "mark": list(trace.station.spec.mark)},
        "status": trace.status,
        "reason": trace.reason,
        "message": None
        if trace.status == "ok"
        else halt_message(cell, trace.reason, trace.station and trace.station.name, reading.station_id),
        "shift_mm": detail and detail.shift_mm,
        "rotation_deg": detail and detail.rotation_deg,
        "phi_deg": detail and detail.phi_deg,
        "correction": None if detail is None or detail.correction is None else detail.correction.tolist(),
        "poses": [],  # the taught poses, corrected
        "retreat": None,  # the retreat from the work pose ([cell.motion] retreat_mm), corrected
    }
    taught = 0 if trace.station is None else len(trace.station.poses)
    for i, move in enumerate(trace.moves):
        native = {}
        for target_name in cell.targets:
            fmt = get_target(target_name).pose_format
            native[target_name] = list(shown_values(POSE_FORMATS[fmt][2](move.tcp2base), fmt))
        pose = {"name": move.pose_name, "motion": move.kind, "targets": native}
        if i < taught:
            report["poses"].append(pose)
        else:
            report["retreat"] = pose
    return report


def format_report(report: dict) -> str:
    r = report["reading"]
    lines = [
        f"cell {report['cell']}: reading station {r['station_id']} "
        f"mark ({r['x_mm']:g}, {r['y_mm']:g}, {r['theta_deg']:g} deg)"
    ]
    if report["station"]:
        s = report["station"]
        lines.append(
            f"station {s['id']} {s['name']}: calibration mark ({s['mark'][0]:g}, "
            f"{s['mark'][1]:g}, {s['mark'][2]:g} deg)"
        )
    if report["shift_mm"] is not None:
        lines.append(
            f"shift {format_literal(report['shift_mm'], 4)} mm, "
            f"rotation {format_literal(report['rotation_deg'], 4)} deg"
            + (
                f", phi {format_literal(report['phi_deg'], 4)} deg (angle_sign {report['angle_sign']:+d})"
                if report["phi_deg"] is not None
                else ""
            )
        )
    if report["status"] == "halt":
        lines.append(f"HALT ({report['reason']}): {report['message']}")
        return "\n".join(lines)
    lines.append("guard ok")
    for pose in [*report["poses"], *([report["retreat"]] if report["retreat"] else [])]:
        lines.append(f"{pose['name']} ({pose['motion']} move):")
        for target, values in pose["targets"].items():
            facts = get_target(target)
            lines.append(f"  {target:<7}{pose_text(values, facts.pose_format)}    {facts.pose_units}")
    return "\n".join(lines)
