"""Frame correction with refinement (source 001): the kind, its simulated camera and vision PC."""

from codegen.kinds.frame.camera import CameraModel, SimulatedCamera
from codegen.kinds.frame.kind import FrameCase, FrameKind, FrameSpec, expected_frame_trace, frame_offset
from codegen.kinds.frame.vision_pc import VisionPC

__all__ = [
    "CameraModel",
    "FrameCase",
    "FrameKind",
    "FrameSpec",
    "SimulatedCamera",
    "VisionPC",
    "expected_frame_trace",
    "frame_offset",
]
