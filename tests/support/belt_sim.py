"""A simulated belt for the conveyor calibration tests: true scale, frame and counter, noisy touches."""

import math

import numpy as np

TRUE_E = -8.1234  # counts per mm; negative: the counter runs down as the belt travels
TRUE_ORIGIN = np.array([800.0, -300.0, 150.0])
YAW_DEG, ROLL_DEG = 30.0, 2.0  # the belt's direction in the base, and its tilt about its own axis
BITS = 16
START_COUNT = 2_000  # counts down through 0: the 16-bit counter rolls over during the touches
CAMERA_UPSTREAM_MM = 1_200.0
# the robot's own encoder (UR: encoder_get_tick_count(0), its filtered count [0; 65536[): another encoder on the belt,
# counting up as the belt travels, rolling over during the touches
TRUE_TICKS = 5.0931  # ticks per mm
TICK_START = 61_000


def belt2base() -> np.ndarray:
    yaw, roll = math.radians(YAW_DEG), math.radians(ROLL_DEG)
    rz = np.array([[math.cos(yaw), -math.sin(yaw), 0], [math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]])
    ry = np.array([[math.cos(roll), 0, math.sin(roll)], [0, 1, 0], [-math.sin(roll), 0, math.cos(roll)]])
    out = np.eye(4)
    out[:3, :3] = rz @ ry  # belt x across, y along the travel, z its normal
    out[:3, 3] = TRUE_ORIGIN
    return out


def count_at(s_mm: float) -> int:
    """The raw counter when the cone is s mm downstream of the origin."""
    return round(START_COUNT + TRUE_E * (s_mm + 1_000.0)) % 2**BITS


def ticks_at(s_mm: float) -> int:
    """The robot's filtered tick count when the cone is s mm downstream of the origin."""
    return round(TICK_START + TRUE_TICKS * (s_mm + 1_000.0)) % 2**BITS


def touches(noise_mm: float = 0.05, seed: int = 7) -> list[tuple[float, float, float, int, str]]:
    """Four touches along the belt (1,000 mm upstream to the origin), then one 200 mm beside it."""
    rng = np.random.default_rng(seed)
    frame = belt2base()
    rows = []
    for s in (-1_000.0, -650.0, -300.0, 0.0):
        p = frame @ np.array([0.0, s, 0.0, 1.0])
        rows.append((*(p[:3] + rng.normal(0, noise_mm, 3)), count_at(s), "belt"))
    p = frame @ np.array([200.0, -150.0, 0.0, 1.0])
    rows.append((*(p[:3] + rng.normal(0, noise_mm, 3)), count_at(-150.0), "side"))
    return rows


def csv_text(rows, ticks: bool = False) -> str:
    """The touches as the calibration reads them; ticks: with the robot's tick count at each belt touch (the
    rows in touches()' order: the side point has none)."""
    if not ticks:
        lines = ["x,y,z,count,role"] + [f"{x:.3f},{y:.3f},{z:.3f},{c},{r}" for x, y, z, c, r in rows]
        return "\n".join(lines) + "\n"
    places = (-1_000.0, -650.0, -300.0, 0.0)
    lines = ["x,y,z,count,role,ticks"] + [
        f"{x:.3f},{y:.3f},{z:.3f},{c},{r}," + (str(ticks_at(places[k])) if r == "belt" else "")
        for k, (x, y, z, c, r) in enumerate(rows)
    ]
    return "\n".join(lines) + "\n"


def camera_counts() -> tuple[int, int]:
    return count_at(-CAMERA_UPSTREAM_MM), count_at(0.0)
