"""A second way to choose a solution by a configuration, for the tests only: enumerate every turn of every
axis within the limits, then filter (codegen/robot/config.py shifts each axis to its turn directly)."""

from __future__ import annotations

import math

import numpy as np

from codegen.robot.config import abb_confdata, kuka_status, kuka_turn
from codegen.robot.opw import OPW

TURN = 360.0
LIMIT_SLACK_DEG = 1e-9


def turn_variants(solutions_deg: np.ndarray, limits_deg: np.ndarray) -> np.ndarray:
    """Every q + 360 k per axis (k = 0 first, then -1, +1, -2, ...) of each complete solution row that lies
    within the limits: (..., 6) solutions, (6, 2) [low, high] deg -> (m, 6), source rows in order."""
    rows = np.asarray(solutions_deg, dtype=float).reshape(-1, 6)
    rows = rows[~np.isnan(rows).any(axis=1)]
    limits = np.asarray(limits_deg, dtype=float).reshape(6, 2)
    for axis in range(6):
        if len(rows) == 0:
            break
        low, high = limits[axis]
        values = rows[:, axis]
        k_low = math.floor((low - values.max()) / TURN)
        k_high = math.ceil((high - values.min()) / TURN)
        ks = np.array(sorted(range(k_low, k_high + 1), key=lambda k: (abs(k), k)), dtype=float)
        shifted = np.repeat(rows[:, None, :], len(ks), axis=1)
        shifted[:, :, axis] += TURN * ks
        inside = (shifted[:, :, axis] >= low - LIMIT_SLACK_DEG) & (shifted[:, :, axis] <= high + LIMIT_SLACK_DEG)
        rows = shifted[inside]
    return rows


def _first(candidates: np.ndarray, match: np.ndarray) -> np.ndarray | None:
    return candidates[int(np.argmax(match))] if match.any() else None


def select_abb(kin: OPW, solutions_deg: np.ndarray, conf, limits_deg: np.ndarray) -> np.ndarray | None:
    """The solution (any branch, any turn within the limits) whose confdata equals conf = (cf1, cf4, cf6, cfx):
    cfx names the branch, cf1/cf4/cf6 the quadrant hence the turn of axes 1, 4, 6. None when none does."""
    candidates = turn_variants(solutions_deg, limits_deg)
    if len(candidates) == 0:
        return None
    match = (abb_confdata(kin, candidates) == np.asarray(conf, dtype=int)).all(axis=-1)
    return _first(candidates, match)


def select_kuka(kin: OPW, solutions_deg: np.ndarray, status: int, turn: int, limits_deg: np.ndarray):
    """The solution (any branch, any turn within the limits) with these Status bits 0-2 and Turn bits 0-5
    (a PTP to an E6POS with S and T). None when none has them."""
    candidates = turn_variants(solutions_deg, limits_deg)
    if len(candidates) == 0:
        return None
    s = np.atleast_1d(np.asarray(kuka_status(kin, candidates)))
    t = np.atleast_1d(np.asarray(kuka_turn(candidates)))
    match = ((s & 7) == (int(status) & 7)) & ((t & 63) == (int(turn) & 63))
    return _first(candidates, match)


def nearest(solutions_deg: np.ndarray, q_ref_deg: np.ndarray, limits_deg: np.ndarray, metric: str = "euclidean"):
    """The solution (any branch, any turn within the limits) closest to q_ref: "euclidean" (sum of squared
    axis differences, UR's get_inverse_kin(x, qnear) rule) or "max" (largest axis difference). None if none."""
    candidates = turn_variants(solutions_deg, limits_deg)
    if len(candidates) == 0:
        return None
    delta = candidates - np.asarray(q_ref_deg, dtype=float)
    if metric == "euclidean":
        distance = np.sum(delta * delta, axis=-1)
    elif metric == "max":
        distance = np.max(np.abs(delta), axis=-1)
    else:
        raise ValueError(f"metric: expected 'euclidean' or 'max', got {metric!r}")
    return candidates[int(np.argmin(distance))]
