"""The distance engine's cheap bounds and its measuring of the near pairs against every pair measured exactly."""

from __future__ import annotations

import numpy as np
import pytest

from codegen.robot.arms import catalogue
from codegen.world.engine import GROUPS, Scene, distance
from codegen.world.solids import Box, Capsule, Cylinder, Floor, World, tool_cylinder, translation


def _turned(rng, x: float, y: float, z: float) -> np.ndarray:
    """A pose at (x, y, z) turned about a random axis by a random angle."""
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    angle = rng.uniform(0.0, np.pi)
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    out = translation(x, y, z)
    out[:3, :3] = np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)
    return out


def _scene(seed: int) -> Scene:
    """UR5e with a tool and a part among turned boxes and cylinders, a capsule and a floor, near its reach."""
    rng = np.random.default_rng(seed)
    solids = {"floor": Floor(-400.0)}
    for i in range(3):
        solids[f"box {i}"] = Box(tuple(rng.uniform(40.0, 700.0, 3)), _turned(rng, *rng.uniform(-700.0, 700.0, 3)))
        solids[f"cylinder {i}"] = Cylinder(float(rng.uniform(20.0, 200.0)), float(rng.uniform(40.0, 800.0)),
                                           _turned(rng, *rng.uniform(-700.0, 700.0, 3)))
    solids["post"] = Capsule(60.0, (500.0, -300.0, -400.0), (500.0, -300.0, 400.0))
    tool = tool_cylinder(translation(0.0, 0.0, 150.0), 25.0)
    part = Box((60.0, 60.0, 80.0), translation(0.0, 0.0, 190.0))
    return Scene(catalogue()["UR5e"], World(solids), tool=tool, part=part)


def _exact(scene: Scene, q: np.ndarray) -> list[tuple[int, float, str, str]]:
    """Every pair measured (group, signed distance, body, other), in the bounds' layout."""
    frames = scene.arm.kin.link_frames(q)
    out = []
    for body in scene.bodies:
        for name, solid in zip(scene.names, scene.solids, strict=True):
            out.append((0, distance(body.shape, frames[body.frame], solid, np.eye(4))[0], body.name, name))
    for i, j in scene.pairs:
        one, other = scene.bodies[i], scene.bodies[j]
        d = distance(one.shape, frames[one.frame], other.shape, frames[other.frame])[0]
        out.append((min(one.frame, other.frame), d, one.name, other.name))
    return out


CONFIGURATIONS = np.random.default_rng(7).uniform(-180.0, 180.0, (40, 6))


@pytest.mark.parametrize("seed", range(4))
def test_every_bound_is_below_the_pairs_distance(seed):
    scene = _scene(seed)
    inside = 0
    for q in CONFIGURATIONS:
        bounds, skip = scene._bounds(scene.poses(q)[0][:, :3, 3])
        exact = _exact(scene, q)
        assert len(bounds) == len(exact) == len(skip)
        for bound, (_, d, body, other) in zip(bounds.tolist(), exact, strict=True):
            assert bound <= d + 1e-6, (body, other, bound, d)
            inside += d < 0
    assert inside  # overlaps are among them: a bound below a negative depth too


@pytest.mark.parametrize("seed", range(4))
def test_the_near_pairs_measured_give_what_every_pair_measured_gives(seed):
    scene = _scene(seed)
    rng = np.random.default_rng(seed)
    skipped = 0
    for q in CONFIGURATIONS:
        caps = rng.uniform(0.0, 600.0, GROUPS)
        below = float(rng.choice([np.inf, rng.uniform(-50.0, 400.0)]))
        exact = [(g, d, body, other) for (g, d, body, other), skip in
                 zip(_exact(scene, q), scene._bounds(scene.poses(q)[0][:, :3, 3])[1], strict=True) if not skip]
        before = scene.queries
        known, found = scene.least_by_group(scene.poses(q)[0], caps, below)
        skipped += len(exact) - (scene.queries - before)
        for g in range(GROUPS):
            group = [d for one, d, _, _ in exact if one == g]
            want = min(min(group), caps[g]) if group else np.inf
            assert known[g] == pytest.approx(want, abs=1e-6), (g, known[g], want)
        nearest = min(exact, key=lambda pair: pair[1])
        if nearest[1] < below:
            assert found is not None and found.distance == pytest.approx(nearest[1], abs=1e-6)
            assert (found.body, found.other) == nearest[2:] or found.distance == pytest.approx(
                sorted(d for _, d, _, _ in exact)[1], abs=1e-6)  # a tie: either of the two
        else:
            assert found is None
    assert skipped > 0  # the bounds left pairs unmeasured
