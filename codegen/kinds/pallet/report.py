"""`codegen pallet`: each box's poses in pallet and base frames (JSON: docs/kinds/pallet.md), a cycle-time estimate."""

from __future__ import annotations

from dataclasses import dataclass
from itertools import pairwise
from pathlib import Path

import numpy as np

from codegen.kinds.pallet.patterns import cell_angle
from codegen.kinds.pallet.section import Pallet, pallets_of
from codegen.kinds.pallet.shape import full_cycle, pallet_shape
from codegen.model.cell import load_cell
from codegen.poses import zyx_deg_from_rotmat


def xyzabc(pose: np.ndarray) -> list[float]:
    """mm and deg, 6 decimals, no negative zero."""
    values = [*pose[:3, 3], *zyx_deg_from_rotmat(pose[:3, :3])]
    return [round(float(v), 6) + 0.0 for v in values]


def _pose(pose: np.ndarray, pallet2base: np.ndarray) -> dict:
    return {"pallet": xyzabc(pose), "base": xyzabc(pallet2base @ pose)}


def cycle_estimate(cell, pallet: Pallet) -> dict:
    """Seconds per pallet from the full cycle's moves (the reference's: codegen/kinds/pallet/cycle.py), each one's
    path length over its programmed speed, a blended pose's corner cut by the zone (the chord between the points
    zone_mm before and after it); no acceleration (an exact stop costs the arm's braking and starting, not counted),
    no gripper or interlock time, no home move."""

    moves = full_cycle(cell, pallet)
    travel = work = saving = 0.0
    for before, move in pairwise(moves):
        length = float(np.linalg.norm(move.tcp2base[:3, 3] - before.tcp2base[:3, 3]))
        if move.speed_mm_s == cell.motion.work_speed_mm_s:
            work += length
        else:
            travel += length
    zone, seconds_saved = pallet.zone_mm, 0.0
    blended = [i for i in range(1, len(moves) - 1) if not moves[i].exact and zone > 0]
    for i in blended:
        u = moves[i - 1].tcp2base[:3, 3] - moves[i].tcp2base[:3, 3]
        w = moves[i + 1].tcp2base[:3, 3] - moves[i].tcp2base[:3, 3]
        if min(np.linalg.norm(u), np.linalg.norm(w)) < 2 * zone:
            continue  # a leg too short for the zone (the arm passes the pose closer): no saving counted
        cosine = float(np.dot(u, w) / (np.linalg.norm(u) * np.linalg.norm(w)))
        cut = 2 * zone - 2 * zone * np.sqrt((1 - min(1.0, max(-1.0, cosine))) / 2)  # 2z - 2z sin(angle / 2)
        saving += cut
        seconds_saved += cut / 2 / moves[i].speed_mm_s + cut / 2 / moves[i + 1].speed_mm_s
    seconds = travel / cell.motion.speed_mm_s + work / cell.motion.work_speed_mm_s - seconds_saved
    return {
        "travel_mm": round(travel, 1),
        "work_mm": round(work, 1),
        "speed_mm_s": cell.motion.speed_mm_s,
        "work_speed_mm_s": cell.motion.work_speed_mm_s,
        "stops": sum(1 for m in moves if m.exact or zone == 0),
        "blends": len(blended),
        "corner_saving_mm": round(float(saving), 1),
        "seconds": round(float(seconds), 1),
    }


def pallet_report(cell, pallet: Pallet) -> dict:
    shape = pallet_shape(cell, pallet)
    frame, placed = shape.pallet2base, shape.placements
    return {
        "name": pallet.name,
        "frame": [[round(float(v), 9) + 0.0 for v in row] for row in frame],
        "layers": [
            {"layer": n, "pattern": pallet.cycle[(n - 1) % len(pallet.cycle)], "top_mm": round(shape.tops[n], 6)}
            for n in range(1, pallet.layers + 1)
        ],
        "boxes": [
            {
                "layer": p.layer,
                "box": p.number,
                "pattern": p.pattern,
                "angle": cell_angle(pallet, p.box),
                "target": _pose(p.target, frame),
                "entry": _pose(p.entry, frame),
                "approach": _pose(p.approach, frame),
                "retreat": _pose(p.retreat, frame),
            }
            for p in placed
        ],
        "cycle": cycle_estimate(cell, pallet),
    }


def report(data: PalletFile) -> dict:
    return {
        "cell": data.name,
        "pallets": [pallet_report(data.cell, p) for p in data.pallets],
        "warnings": list(data.warnings),
    }


def text(result: dict) -> str:
    lines = [f"cell {result['cell']}"]
    for pallet in result["pallets"]:
        count = len(pallet["boxes"])
        lines.append(f"pallet {pallet['name']}: {count} boxes in {len(pallet['layers'])} layers")
        for layer in pallet["layers"]:
            lines.append(f"  layer {layer['layer']}: pattern {layer['pattern']}, top at z {layer['top_mm']:g} mm")
        lines.append("  layer box  target (pallet frame: x y z a b c)          entry z   approach (x y z)")
        for b in pallet["boxes"]:
            t, e, a = b["target"]["pallet"], b["entry"]["pallet"], b["approach"]["pallet"]
            lines.append(
                f"  {b['layer']:5d} {b['box']:3d}  ({', '.join(f'{v:g}' for v in t)})".ljust(60)
                + f"{e[2]:8g}   ({a[0]:g}, {a[1]:g}, {a[2]:g})"
            )
        cycle = pallet["cycle"]
        if cycle is not None:
            lines.append(
                f"  cycle estimate: {cycle['seconds']:g} s per pallet ({cycle['travel_mm']:g} mm at "
                f"{cycle['speed_mm_s']:g} mm/s, {cycle['work_mm']:g} mm at {cycle['work_speed_mm_s']:g} mm/s; "
                f"{cycle['stops']} exact stops, {cycle['blends']} blended poses saving "
                f"{cycle['corner_saving_mm']:g} mm; "
                "no acceleration, no gripper time)"
            )
    return "\n".join(lines)


@dataclass(frozen=True)
class PalletFile:
    """What `codegen pallet` reads: the cell's name and pallets (a file may hold no stations)."""

    name: str
    source: str
    pallets: tuple[Pallet, ...]
    warnings: tuple[str, ...]
    motion: object  # codegen.model.motion.MotionSettings: the speeds of the cycle-time estimate
    cell: object = None  # the whole codegen.model.cell.Cell


def load_pallet_file(path: str | Path) -> PalletFile:
    """A cell file's pallets (a cell of pallets alone needs no camera and no stations)."""
    cell = load_cell(path)
    return PalletFile(cell.name, str(path), pallets_of(cell), cell.warnings, cell.motion, cell)
