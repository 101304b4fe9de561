"""Frame correction with refinement (source 001): the kind and its simulated camera."""

from codegen.kinds.frame.kind import FrameCase, FrameKind, FrameSpec, expected_frame_trace, frame_offset
from codegen.sim.camera import CameraModel, SimulatedCamera

__all__ = [
    "CameraModel",
    "FrameCase",
    "FrameKind",
    "FrameSpec",
    "SimulatedCamera",
    "expected_frame_trace",
    "frame_offset",
]
