"""The sensor frame from the setup run's centres and contacts (float64; frame_derivation.py proves the formulas)."""

from __future__ import annotations

import math

import numpy as np


def solve_yaw(step_mm: float, delta_mm: float) -> float:
    """tX (or tY) from the centre's step over the circles' step (float64; ValueError where it has no root)."""
    if delta_mm == 0.0:
        raise ValueError("the circles must be apart (delta = 0: the yaw is not seen)")
    k = step_mm / delta_mm
    if abs(k) > 0.5:
        raise ValueError(f"a centre step {step_mm} mm over {delta_mm} mm has no yaw (|k| > 1/2)")
    return 0.0 if k == 0.0 else (1.0 - math.sqrt(1.0 - 4.0 * k * k)) / (2.0 * k)


def solve_frame(
    y_x: tuple[float, float],
    x_y: tuple[float, float],
    delta_mm: float,
    z_x: tuple[float, float],
    z_y: tuple[float, float],
    half_span_mm: float,
    radius_mm: float,
) -> dict:
    """The beams in the named S from the setup run's measurements (float64): y_x = beam X's centre y at c = 0 and
    c = (delta, 0); x_y = beam Y's centre x at c = 0 and (0, delta); z_x, z_y = the contacts' heights L either side
    of the crossing along each beam. Returns the crossing d (mm), the yaws tX, tY and the slopes sX, sY."""
    t_x = solve_yaw(y_x[1] - y_x[0], delta_mm)
    t_y = solve_yaw(x_y[1] - x_y[0], delta_mm)
    system = np.array([[-t_x, 1.0], [1.0, -t_y]])
    if abs(np.linalg.det(system)) < 1e-9:
        raise ValueError("the beams are parallel in the plane: no crossing")
    d_xy = np.linalg.solve(system, [y_x[0] * (1 + t_x * t_x), x_y[0] * (1 + t_y * t_y)])
    if half_span_mm <= 0.0:
        raise ValueError("the search points must lie apart along each beam (L > 0)")
    s_x = (z_x[1] - z_x[0]) / (2.0 * half_span_mm)
    s_y = (z_y[1] - z_y[0]) / (2.0 * half_span_mm)
    d_z = (z_x[0] + z_x[1]) / 2.0 - radius_mm * abs(s_x)
    return {"d": (float(d_xy[0]), float(d_xy[1]), float(d_z)), "t_x": t_x, "t_y": t_y, "s_x": s_x, "s_y": s_y}
