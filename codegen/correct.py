"""`codegen correct`: the reference result for one reading in every target's native pose format."""

from __future__ import annotations

from codegen.cell import Cell
from codegen.controllers import get_target
from codegen.poses import FORMAT_DECIMALS, POSE_FORMATS
from codegen.reference import Reading, expected_trace, halt_message


def correct_report(cell: Cell, reading: Reading) -> dict:
    trace = expected_trace(cell, reading)
    report: dict = {
        "cell": cell.name,
        "reading": {"station_id": reading.station_id, "x_mm": reading.x, "y_mm": reading.y, "theta_deg": reading.theta},
        "angle_sign": cell.angle_sign,
        "station": None
        if trace.station is None
        else {"id": trace.station.id, "name": trace.station.name, "mark": list(trace.station.mark)},
        "status": trace.status,
        "reason": trace.reason,
        "message": None if trace.status == "ok" else halt_message(cell, trace, reading.station_id),
        "shift_mm": trace.shift_mm,
        "rotation_deg": trace.rotation_deg,
        "phi_deg": trace.phi_deg,
        "correction": None if trace.base2base_new is None else trace.base2base_new.tolist(),
        "poses": [],
    }
    for move in trace.moves:
        native = {}
        for target_name in cell.targets:
            fmt = get_target(target_name).pose_format
            native[target_name] = [v + 0.0 for v in POSE_FORMATS[fmt][2](move.base2tcp)]
        report["poses"].append({"name": move.pose_name, "motion": move.kind, "targets": native})
    return report


UNITS = {
    "ur": "x y z [m], rx ry rz [rad, rotation vector]",
    "kuka": "X Y Z [mm], A B C [deg]",
    "abb": "x y z [mm], q1 q2 q3 q4 [quaternion]",
    "dtrans": "x y z [mm], rx ry rz [deg]",
}


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
            f"shift {report['shift_mm']:.4f} mm, rotation {report['rotation_deg']:.4f} deg"
            + (
                f", phi {report['phi_deg']:.4f} deg (angle_sign {report['angle_sign']:+d})"
                if report["phi_deg"] is not None
                else ""
            )
        )
    if report["status"] == "halt":
        lines.append(f"HALT ({report['reason']}): {report['message']}")
        return "\n".join(lines)
    lines.append("guard ok")
    for pose in report["poses"]:
        lines.append(f"{pose['name']} ({pose['motion']} move):")
        for target, values in pose["targets"].items():
            decimals = FORMAT_DECIMALS[get_target(target).pose_format]
            shown = " ".join(f"{v:.{n}f}" for v, n in zip(values, decimals, strict=True))
            lines.append(f"  {target:<7}{shown}    {UNITS[target]}")
    return "\n".join(lines)
