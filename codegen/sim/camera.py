"""Simulated camera for frame-mode stations: what it reports from a photo pose, with hand-eye errors."""

from __future__ import annotations

import math
import random
from dataclasses import dataclass

import numpy as np

from codegen.poses import concat, invert


@dataclass(frozen=True)
class CameraModel:
    """How the real camera differs from its calibration, and its noise (all optional).

    The calibrated hand-eye map takes pixels to frame millimetres; the real one is off by a scale
    factor (1 + scale_error) and a rotation (rotation_error_deg) about the photo axis, so the
    program, applying the calibrated map, reads the mark offset turned and scaled by these errors.
    """

    scale_error: float = 0.0
    rotation_error_deg: float = 0.0
    noise_px: float = 0.0
    noise_deg: float = 0.0
    seed: int = 0
    fault_at_photo: int = 0  # > 0: that photo returns NaN (a failed match), to exercise the guard

    def __str__(self) -> str:
        """As a report names it: only what differs from a perfect camera."""
        parts = [
            f"scale off {self.scale_error * 100:g} %" if self.scale_error else "",
            f"turned {self.rotation_error_deg:g} deg" if self.rotation_error_deg else "",
            f"noise {self.noise_px:g} px / {self.noise_deg:g} deg (seed {self.seed})"
            if self.noise_px or self.noise_deg else "",
            f"photo {self.fault_at_photo} fails" if self.fault_at_photo else "",
        ]
        return ", ".join(p for p in parts if p) or "exact"


def mark_offset_seen(
    calib2base: np.ndarray, photo2frame: np.ndarray, tcp2base: np.ndarray, mark2base: np.ndarray
) -> tuple[float, float, float]:
    """The mark in the frame the camera believes it is photographing from: (x mm, y mm, yaw deg).

    The camera rides on the tool; at calibration the tool at photo2frame saw the mark at the frame
    origin. Now the tool is at tcp2base, so the frame it implies is concat(frame2photo, tcp2base).
    """
    frame2base = concat(invert(photo2frame), tcp2base)  # the frame the tool's pose implies
    mark2frame = concat(mark2base, invert(frame2base))
    yaw = math.degrees(math.atan2(mark2frame[1, 0], mark2frame[0, 0]))
    return float(mark2frame[0, 3]), float(mark2frame[1, 3]), yaw


class SimulatedCamera:
    """Answers photo requests in pixels (u, v) and an image angle, as the real camera would: from the
    physical situation and the image geometry alone. It does not know the cell's angle_sign: the
    angle it reports turns the way the image axes turn, so a mirrored image (a hand-eye map with a
    negative determinant) reports a turn of the mark the other way round."""

    def __init__(self, model: CameraModel, pixel_to_mm, calib2base, photo2frame, mark2base) -> None:
        self.model = model
        self.pixel_to_mm = np.array(pixel_to_mm, dtype=float)
        self.calib2base, self.photo2frame, self.mark2base = calib2base, photo2frame, mark2base
        self.photos = 0
        self._rng = random.Random(model.seed)

    def photo(self, tcp2base: np.ndarray) -> tuple[float, float, float]:
        self.photos += 1
        if self.photos == self.model.fault_at_photo:
            return math.nan, math.nan, math.nan
        x, y, yaw = mark_offset_seen(self.calib2base, self.photo2frame, tcp2base, self.mark2base)
        # The program applies the calibrated map; the real map is off by the hand-eye error, so the
        # millimetres the program will compute are the true offset turned back and scaled back.
        u, v = self._pixels(x, y)
        u += self._rng.gauss(0.0, self.model.noise_px) if self.model.noise_px else 0.0
        v += self._rng.gauss(0.0, self.model.noise_px) if self.model.noise_px else 0.0
        angle = self._image_angle(yaw) + (self._rng.gauss(0.0, self.model.noise_deg) if self.model.noise_deg else 0.0)
        return float(u), float(v), angle

    def _pixels(self, x: float, y: float) -> np.ndarray:
        """Where a point (x, y) mm of the frame the camera believes in lands in the image. The program
        applies the calibrated map; the real map is off by the hand-eye error, so the millimetres it
        will compute are the true ones turned back and scaled back."""
        err = math.radians(self.model.rotation_error_deg)
        k = 1.0 / (1.0 + self.model.scale_error)
        mx = k * (math.cos(-err) * x - math.sin(-err) * y)
        my = k * (math.sin(-err) * x + math.cos(-err) * y)
        return np.linalg.solve(self.pixel_to_mm[:, :2], np.array([mx, my]) - self.pixel_to_mm[:, 2])

    def _image_angle(self, yaw_deg: float) -> float:
        """The mark's turn from its taught look, measured in the image's own axes (u towards v): the
        angle from its x axis at calibration to its x axis now, both as pixel directions."""
        origin = self._pixels(0.0, 0.0)
        u0, v0 = self._pixels(1.0, 0.0) - origin
        yaw = math.radians(yaw_deg)
        u1, v1 = self._pixels(math.cos(yaw), math.sin(yaw)) - origin
        return math.degrees(math.atan2(u0 * v1 - v0 * u1, u0 * u1 + v0 * v1))
