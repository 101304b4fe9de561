"""The boxes' separating-axis bound never exceeds the collision library's distance; tight when apart on an axis."""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from codegen.world.engine import distance
from codegen.world.solids import Box, Cylinder, bounding_box, separation_bound

EYE = np.eye(4)


def _pose(rng) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = Rotation.random(random_state=rng).as_matrix()
    pose[:3, 3] = rng.uniform(-400.0, 400.0, 3)
    return pose


def test_the_bound_is_at_most_the_distance_apart_or_overlapping():
    rng = np.random.default_rng(7)
    overlapping = apart = 0
    for _ in range(400):
        a = Box(tuple(rng.uniform(20.0, 500.0, 3)), _pose(rng))
        b = Box(tuple(rng.uniform(20.0, 500.0, 3)), _pose(rng))
        exact = distance(a, EYE, b, EYE)[0]
        overlapping, apart = overlapping + (exact < 0), apart + (exact > 0)
        assert separation_bound(a, b) <= exact + 1e-6
    assert overlapping > 50 and apart > 50  # both sides of contact were tried


def test_boxes_apart_along_an_axis_are_bounded_by_their_gap():
    moved = np.eye(4)
    moved[:3, 3] = (300.0, 0.0, 0.0)
    assert separation_bound(Box((100.0, 100.0, 100.0)), Box((100.0, 100.0, 100.0), moved)) == 200.0
    moved[:3, 3] = (60.0, 0.0, 0.0)  # 40 mm into each other
    assert separation_bound(Box((100.0, 100.0, 100.0)), Box((100.0, 100.0, 100.0), moved)) == -40.0


def test_a_cylinders_bounding_box_holds_it():
    cylinder = Cylinder(50.0, 200.0, _pose(np.random.default_rng(3)))
    box = bounding_box(cylinder)
    assert box.size == (100.0, 100.0, 200.0) and np.array_equal(box.pose, cylinder.pose)
