"""The simulated vision PC of frame mode: answers the program's photo requests through its variables."""

from __future__ import annotations

from codegen.dialects.core.machine import Machine
from codegen.dialects.core.values import RunError


class VisionPC:
    """The vision PC's side of the photo handshake, a device of Program.run: when the program waits
    with a photo requested and not yet acknowledged, take the picture from where the robot last
    moved, write the reading (u, v, angle) and acknowledge the request.

    photo_io_names: the handshake's variable or register names (request, ack, u, v, angle) as the
    target's facts name them, or None for a program without the handshake; camera: a
    SimulatedCamera, or None (a wait for a photo is then an error)."""

    def __init__(self, photo_io_names: dict | None, camera=None) -> None:
        self.names = photo_io_names
        self.camera = camera

    @classmethod
    def for_target(cls, target, camera=None) -> VisionPC:
        """The vision PC wired to the handshake names of a target's facts ([program] photo)."""
        return cls(target.program.get("photo"), camera)

    def on_wait(self, machine: Machine, where: str) -> bool:
        io = self.names
        if not io:
            return False
        request, ack = machine.read_variable(io["request"]), machine.read_variable(io["ack"])
        if request is None or request == ack:
            return False
        if self.camera is None:
            raise RunError(
                f"{where}: the program waits for a photo and no camera is attached "
                "(codegen verify attaches a simulated one)"
            )
        if not machine.trace.moves:
            raise RunError(f"{where}: a photo was requested before the robot moved to a photo pose")
        u, v, angle = self.camera.photo(machine.trace.moves[-1].tcp2base)
        for key, value in (("u", u), ("v", v), ("angle", angle), ("ack", request)):
            if not machine.write_variable(io[key], value):
                raise RunError(f"{machine.program.name}: the photo interface variable {io[key]} is not declared")
        return True
