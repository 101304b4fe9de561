"""The cell's objects in the page, from its model: stations (mark, taught poses, bench), pallets, belt, laser."""

from __future__ import annotations

from dataclasses import fields

import numpy as np

from codegen.kinds.pallet.analysis import frame_matrix
from codegen.kinds.pallet.patterns import label_normal
from codegen.kinds.pallet.stack import layer_top, placements
from codegen.poses import matrix_from_rotation_translation, rotmat_from_zyx_deg
from codegen.protocol import get_kind, kinds
from codegen.sim.beams import Sensors
from codegen.view.scene import box, frame, line, point, translated

BENCH_MARGIN_MM = 120.0  # the frame-mode bench reaches this far beyond the taught poses around its mark
SLAB_MM = 20.0  # a bench's, a pallet's, a belt's and a table's thickness as drawn (the cell gives none)
LABEL_MM = 1.0  # a box's label, drawn as a sheet this thick on the label side
BELT_MARGIN_MM = 150.0  # the belt drawn this far beyond its window and camera line
BEAM_REACH_MM = next(f.default for f in fields(Sensors) if f.name == "reach")  # each sensor to the crossing


def point_station(cell, station) -> list[dict]:
    """The mark at calibration (x, y, theta in the base frame: drawn at the work pose's height, the cell gives no
    height) and the taught poses in the order the arm visits them."""
    x, y, theta = station.spec.mark
    work = station.poses[-1].matrix()
    mark = matrix_from_rotation_translation(rotmat_from_zyx_deg(theta, 0.0, 0.0), (x, y, work[2, 3]))
    out = [frame(mark, f"{station.name}: mark", "mark", 40.0)]
    out += [frame(p.matrix(), f"{station.name}: {p.name}", "taught") for p in station.path]
    out.append(line([p.matrix()[:3, 3] for p in station.path], "taught", dashed=True))
    return out


def frame_station(cell, station) -> list[dict]:
    """The user frame on the mark (the bench), the photo pose and the poses taught in the frame."""
    user2base = station.spec.frame.matrix()
    poses = [user2base @ p.matrix() for p in station.path]
    photo = user2base @ station.spec.photo.matrix()
    local = np.array([np.linalg.solve(user2base, p)[:3, 3] for p in [*poses, photo]])
    low = np.minimum(local.min(axis=0)[:2], 0.0) - BENCH_MARGIN_MM
    high = np.maximum(local.max(axis=0)[:2], 0.0) + BENCH_MARGIN_MM
    centre = translated(user2base, ((low[0] + high[0]) / 2, (low[1] + high[1]) / 2, -SLAB_MM / 2))
    out = [
        box(centre, (*(high - low), SLAB_MM), "bench", f"{station.name}: bench"),
        frame(user2base, f"{station.name}: user frame (mark)", "mark", 80.0),
        frame(photo, f"{station.name}: photo", "camera"),
    ]
    out += [frame(p, f"{station.name}: {t.name}", "taught") for p, t in zip(poses, station.path, strict=True)]
    out.append(line([p[:3, 3] for p in poses], "taught", dashed=True))
    return out


def pallet_objects(cell, pallets) -> list[dict]:
    out = []
    for pallet in pallets:
        out += _pallet(pallet)
    return out


def _pallet(pallet) -> list[dict]:
    """The pallet (its top at the frame's z = 0), every box of the full stack layer by layer with its label side,
    the slip sheets and the pick place Q."""
    pallet2base = frame_matrix(pallet)
    length, width = pallet.size
    out = [
        box(translated(pallet2base, (length / 2, width / 2, -SLAB_MM / 2)), (length, width, SLAB_MM), "pallet"),
        frame(pallet2base, f"pallet {pallet.name}", "pallet", 120.0),
    ]
    bx, by, bz = pallet.box
    for p in placements(pallet):
        top = layer_top(pallet, p.layer)
        turn = rotmat_from_zyx_deg(p.box.ccw_deg, 0.0, 0.0)
        centre = pallet2base @ matrix_from_rotation_translation(turn, (p.box.x, p.box.y, top - bz / 2))
        out.append(box(centre, (bx - 2.0, by - 2.0, bz), "box", f"{pallet.name}: layer {p.layer} box {p.number}"))
        nx, ny = label_normal(p.box)  # the label on the long side at -y at angle 0
        face = by / 2 - 1.0 + LABEL_MM / 2
        label = pallet2base @ matrix_from_rotation_translation(
            turn, (p.box.x + nx * face, p.box.y + ny * face, top - bz / 2)
        )
        out.append(box(label, (bx * 0.5, LABEL_MM, bz * 0.5), "label"))
    if pallet.slip_every:
        for layer in range(pallet.slip_every, pallet.layers, pallet.slip_every):
            z = layer_top(pallet, layer) + pallet.slip_thickness / 2
            sheet = translated(pallet2base, (length / 2, width / 2, z))
            out.append(box(sheet, (length, width, max(pallet.slip_thickness, 1.0)), "sheet", f"slip sheet {layer}"))
    if pallet.pick is not None:
        pick = pallet.pick.matrix()
        out.append(frame(pick, f"pallet {pallet.name}: pick Q", "pick"))
        table = np.eye(4)
        table[:3, 3] = pick[:3, 3] - (0.0, 0.0, bz + SLAB_MM / 2)
        out.append(box(table, (bx * 1.5, by * 1.5, SLAB_MM), "pick", "pick place"))
    return out


def conveyor_objects(cell, conveyor) -> list[dict]:
    """The belt in its frame (y the travel, z up; the origin the downstream touch), the pick window, the camera's
    line upstream and the place."""
    belt2base = conveyor.frame()
    if belt2base is None:
        return []
    pick = conveyor.pick
    across = pick.x_range_mm if pick is not None else (-100.0, 100.0)
    window = pick.window_mm if pick is not None else (0.0, 0.0)
    camera = -(conveyor.camera_offset_mm or 0.0)
    start, end = min(camera, window[0]) - BELT_MARGIN_MM, max(0.0, window[1]) + BELT_MARGIN_MM
    x0, x1 = across[0] - BELT_MARGIN_MM / 3, across[1] + BELT_MARGIN_MM / 3
    out = [
        box(
            translated(belt2base, ((x0 + x1) / 2, (start + end) / 2, -SLAB_MM / 2)),
            (x1 - x0, end - start, SLAB_MM),
            "belt",
            "belt",
        ),
        frame(belt2base, "belt frame", "belt", 100.0),
    ]
    if conveyor.camera_offset_mm is not None:
        ends = [belt2base @ np.array([x, camera, 1.0, 1.0]) for x in (x0, x1)]
        out.append(line(ends, "camera", "camera line"))
    if pick is not None:
        corners = [(across[0], window[0]), (across[1], window[0]), (across[1], window[1]), (across[0], window[1])]
        ring = [belt2base @ np.array([x, y, 1.0, 1.0]) for x, y in [*corners, corners[0]]]
        out.append(line(ring, "window", "pick window"))
        place = pick.place.matrix()
        out.append(frame(place, "place", "place"))
        table = np.eye(4)
        table[:3, 3] = place[:3, 3] - (0.0, 0.0, 100.0)
        out.append(box(table, (200.0, 200.0, SLAB_MM), "place", "place table"))
    return out


def laser_objects(cell, laser) -> list[dict]:
    """The sensor frame S, its two beams crossing at S's origin (X along +x from its sensor at -x, Y along +y from
    its sensor at -y) and the two sensors."""
    sensor2base = laser.sensor_frame.matrix()
    reach = BEAM_REACH_MM
    out = [frame(sensor2base, "sensor frame S", "sensor", 50.0)]
    for name, axis in (("X", np.array([1.0, 0.0, 0.0])), ("Y", np.array([0.0, 1.0, 0.0]))):
        ends = [sensor2base @ np.array([*(s * reach * axis), 1.0]) for s in (-1.0, 1.0)]
        out.append(line(ends, "beam", f"beam {name}"))
        body = translated(sensor2base, -(reach + 20.0) * axis)
        size = (40.0, 30.0, 30.0) if name == "X" else (30.0, 40.0, 30.0)
        out.append(box(body, size, "sensor", f"sensor {name}"))
    out.append(point(sensor2base[:3, 3], "beam", "crossing"))
    return out


# Each station kind's objects, per station; each other kind's, from its section of the cell.
STATION_OBJECTS = {"point": point_station, "frame": frame_station}
SECTION_OBJECTS = {"pallet": pallet_objects, "conveyor": conveyor_objects, "laser": laser_objects}


def cell_objects(cell) -> list[dict]:
    """Every object of the cell, in the registry's order of the kinds."""
    out = []
    for station in cell.stations:
        out += STATION_OBJECTS[station.kind](cell, station)
    for name in kinds():
        section = get_kind(name).section(cell) if name in SECTION_OBJECTS else None
        if section:
            out += SECTION_OBJECTS[name](cell, section)
    return out


def bounds(objects: list[dict]) -> tuple[list[float], list[float]]:
    """The smallest axis-aligned box holding every object's origin or points (mm)."""
    points = []
    for o in objects:
        if "pose" in o:
            points.append(o["pose"][3:12:4])
        points += o.get("points", [])
        if "position" in o:
            points.append(o["position"])
    if not points:
        return [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    arr = np.array(points, dtype=float)
    return [float(v) for v in arr.min(axis=0)], [float(v) for v in arr.max(axis=0)]
