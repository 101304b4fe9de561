"""The belt in the cell: as the page draws it (the belt in its frame, the pick window, the camera's line, the place)
and as solids (the belt, the place's table)."""

from __future__ import annotations

import numpy as np

from codegen import protocol
from codegen.kinds.conveyor.section import conveyor_of
from codegen.poses import rotmat_from_zyx_deg
from codegen.view.scene import SLAB_MM, box, frame, line, translated
from codegen.world.proof import FROM_THE_HOME, Move, Path
from codegen.world.solids import Box, translation

MARGIN_MM = 150.0  # the belt drawn this far beyond its window and the camera's line
PLACE_TABLE_MM = (200.0, 200.0, 100.0)  # the place's table as drawn: its size, and how far under the place
BELT_DEPTH_MM = 150.0  # the belt's solid under its surface: the belt, its rollers and frame (an estimate)


def _extent(conveyor) -> tuple[tuple[float, float], tuple[float, float]]:
    """The belt's drawn extent in its frame, across (x) and along (y): the window and the camera's line, a margin
    around."""
    pick = conveyor.pick
    across = pick.x_range_mm if pick is not None else (-100.0, 100.0)
    window = pick.window_mm if pick is not None else (0.0, 0.0)
    camera = -(conveyor.camera_offset_mm or 0.0)
    start, end = min(camera, window[0]) - MARGIN_MM, max(0.0, window[1]) + MARGIN_MM
    return (across[0] - MARGIN_MM / 3, across[1] + MARGIN_MM / 3), (start, end)


def solids(conveyor) -> dict[str, Box]:
    """The belt (its surface the frame's z = 0, BELT_DEPTH_MM deep, as far as the page draws it) and, where the part's
    size is given, the place's table: its top under the placed part's bottom (the part as the tool holds it)."""
    belt2base = conveyor.frame()
    if belt2base is None:
        return {}
    (x0, x1), (start, end) = _extent(conveyor)
    centre = translated(belt2base, ((x0 + x1) / 2, (start + end) / 2, -BELT_DEPTH_MM / 2))
    out = {"belt": Box((x1 - x0, end - start, BELT_DEPTH_MM), centre)}
    pick = conveyor.pick
    if pick is not None and pick.part_size_mm is not None:
        cog, size = pick.part_cog_mm, pick.part_size_mm
        bottom = pick.place.matrix() @ np.array([cog[0], cog[1], cog[2] + size[2] / 2, 1.0])
        table = np.eye(4)
        table[:3, 3] = bottom[:3] - (0.0, 0.0, PLACE_TABLE_MM[2] / 2)
        out["belt: place table"] = Box(PLACE_TABLE_MM, table)
    return out


def objects(cell, conveyor) -> list[dict]:
    """The belt (y the travel, z up; the origin the downstream touch), the window, the camera's line upstream and
    the place."""
    belt2base = conveyor.frame()
    if belt2base is None:
        return []
    pick = conveyor.pick
    camera = -(conveyor.camera_offset_mm or 0.0)
    across = pick.x_range_mm if pick is not None else (-100.0, 100.0)
    window = pick.window_mm if pick is not None else (0.0, 0.0)
    (x0, x1), (start, end) = _extent(conveyor)
    centre = translated(belt2base, ((x0 + x1) / 2, (start + end) / 2, -SLAB_MM / 2))
    out = [box(centre, (x1 - x0, end - start, SLAB_MM), "belt", "belt"), frame(belt2base, "belt frame", "belt", 100.0)]
    if conveyor.camera_offset_mm is not None:
        out.append(line([belt2base @ np.array([x, camera, 1.0, 1.0]) for x in (x0, x1)], "camera", "camera line"))
    if pick is not None:
        corners = [(across[0], window[0]), (across[1], window[0]), (across[1], window[1]), (across[0], window[1])]
        ring = [belt2base @ np.array([x, y, 1.0, 1.0]) for x, y in [*corners, corners[0]]]
        out.append(line(ring, "window", "pick window"))
        place = pick.place.matrix()
        out.append(frame(place, "place", "place"))
        table = np.eye(4)
        table[:3, 3] = place[:3, 3] - (0.0, 0.0, PLACE_TABLE_MM[2])
        out.append(box(table, (*PLACE_TABLE_MM[:2], SLAB_MM), "place", "place table"))
    return out


def conveyor_paths(cell, target: str) -> list[Path]:
    """The pick on the target's arm from home, at each corner of the part's place on the belt (across it, its top's
    height: at least the part's own height where its size is given, and where the window starts and where the arm
    may follow it to): a joint move above the part, straight down onto it (the grip), straight up by lift_dz, a joint
    move above the place, straight down to it (the release), up, home. Joints: the solution nearest the pose before."""
    from codegen.kinds.conveyor.reach import follow_mm
    from codegen.robot import solve

    conveyor = conveyor_of(cell)
    pick, robot = conveyor.pick, cell.robot
    arm = robot.arms[target]
    home = np.asarray(robot.home[target], dtype=float)
    grip = np.eye(4)
    grip[:3, :3] = rotmat_from_zyx_deg(*pick.tool_orientation)
    lowest = pick.z_range_mm[0] if pick.part_size_mm is None else max(pick.z_range_mm[0], pick.part_size_mm[2])
    place = pick.place.matrix()
    above_place = place.copy()
    above_place[2, 3] += pick.approach_dz
    part = None if pick.part_size_mm is None else _part(pick, robot.tool.tcp2flange)
    out = []
    for x in pick.x_range_mm:
        for z in (lowest, max(lowest, pick.z_range_mm[1])):
            for y in (pick.window_mm[0], pick.window_mm[1] + follow_mm(cell, target)):
                at = f"conveyor: the part at x {x:g}, y {y:g}, its top {z:g} mm over the belt"
                steps = [
                    ("joint", (x, y, z + pick.approach_dz), "above the part", False, ""),
                    ("linear", (x, y, z - pick.overtravel_mm), "on the part", False, "grip"),
                    ("linear", (x, y, z + pick.lift_dz), "lifted", True, ""),
                ]
                poses = [conveyor.frame() @ translation(*p) @ grip for _k, p, _w, _c, _g in steps]
                poses += [above_place, place, above_place]
                kinds = [k for k, *_ in steps] + ["joint", "linear", "linear"]
                names = [w for _k, _p, w, _c, _g in steps] + ["above the place", "the place", "above the place"]
                held = [c for *_, c, _g in steps] + [True, True, False]
                acts = [g for *_, g in steps] + ["", "release", ""]
                q, moves = home, []
                for pose, kind, name, carrying, act in zip(poses, kinds, names, held, acts, strict=True):
                    sols = solve.branches(arm, solve.flange_poses(pose[None], robot.tool.tcp2flange))[0]
                    q, _ = solve.nearest(arm, sols, q)
                    moves.append(Move(kind, q, f"{at}: {name}", pose, carrying, grip=act))
                moves.append(Move("joint", home, f"{at}: home"))
                out.append(Path(target, home, tuple(moves), part, configuration=FROM_THE_HOME))
    return out


def _part(pick, tcp2flange: np.ndarray) -> Box:
    """The part as the tool holds it, in the flange frame: centred at part_cog_mm in the TCP frame, its edges along
    the TCP frame's axes (as its load has it)."""
    return Box(tuple(pick.part_size_mm), np.asarray(tcp2flange, dtype=float) @ translation(*pick.part_cog_mm))


class ScenePart(protocol.Scene):
    def objects(self, cell) -> list[dict]:
        section = self.kind.section.of(cell)
        return [] if section is None else objects(cell, section)

    def solids(self, cell) -> dict[str, Box]:
        section = self.kind.section.of(cell)
        return {} if section is None else solids(section)

    def carried(self, cell):
        """The belt's part as the tool holds it, where its size is given."""
        section = self.kind.section.of(cell)
        if section is None or section.pick is None or section.pick.part_size_mm is None or cell.robot is None:
            return None
        return _part(section.pick, cell.robot.tool.tcp2flange)

    def paths(self, cell, targets: list[str]) -> list[Path]:
        section = self.kind.section.of(cell)
        if section is None or section.pick is None or cell.robot is None:
            return []
        arms = [t for t in targets if t in cell.robot.arms and t in section.pick.tracking]
        return [path for t in arms for path in conveyor_paths(cell, t)]
