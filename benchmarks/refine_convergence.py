"""Photos to converge with the proven update (R(+alpha)) and with source 001's printed one (R(-alpha)).

The frame starts at the reference, the mark has moved by 40 mm and the given angle, and the hand-eye
map is 3 % off in scale; tolerance 0.02 mm / 0.04 deg, at most 60 photos.
Run: python benchmarks/refine_convergence.py
"""

from __future__ import annotations

import math

from record import Figures

FIGURES = Figures(__file__)


def photos(angle_deg: float, sign: int, scale_error: float = 0.03, limit: int = 60) -> int | None:
    true_x, true_y, true_a = 40.0 * math.cos(0.3), 40.0 * math.sin(0.3), angle_deg
    dx = dy = alpha = 0.0
    k = 1.0 / (1.0 + scale_error)
    for n in range(1, limit + 1):
        # what the camera riding with the current frame reads: the true frame in the current axes
        c, s = math.cos(math.radians(alpha)), math.sin(math.radians(alpha))
        ex, ey = true_x - dx, true_y - dy
        res_x, res_y, gamma = k * (c * ex + s * ey), k * (-s * ex + c * ey), true_a - alpha
        if math.hypot(res_x, res_y) < 0.02 and abs(gamma) < 0.04:
            return n
        ca, sa = math.cos(math.radians(sign * alpha)), math.sin(math.radians(sign * alpha))
        dx, dy, alpha = dx + ca * res_x - sa * res_y, dy + sa * res_x + ca * res_y, alpha + gamma
        if math.hypot(dx, dy) > 1e6:
            return None
    return None


def main() -> None:
    FIGURES.line(f"{'angle':>6} {'R(+alpha)':>10} {'R(-alpha) printed':>18}  (photos; '-' = not within 60)")
    for angle in (0, 5, 10, 20, 25, 29, 31, 40):
        good, printed = photos(angle, +1), photos(angle, -1)
        FIGURES.line(f"{angle:>6} {good if good else '-':>10} {printed if printed else '-':>18}")


if __name__ == "__main__":
    main()
    FIGURES.write()  # the figures into docs/benchmarks.md, dated, with the machine
