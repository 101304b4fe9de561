"""Two displacement sensors beside the controller, a device: crossed beams whose switching outputs follow the pin."""

# Each sensor's switching output is on while its beam meets the pin (a reading within its range). The
# controller reads it once per cycle (codegen/dialects/core/watch.py calls switch(name, t, flange2base) in
# increasing time); the output switches on when the pin reaches hysteresis/2 past the beam and off when it
# has left it by hysteresis/2 (the sensor's own hysteresis keeps a noisy edge from chattering), each
# threshold moved by Gaussian noise of the reading's standard deviation, drawn afresh at every cycle. The
# station knows the true tool (the pin) and the true sensor frame, not what the cell says of them: the
# programs calibrate against this geometry and nothing else.

from __future__ import annotations

import numpy as np

from codegen.sim.beams import Pin, entry_along


class BeamStation:
    """sensor2base: the true sensor frame; pin: the true tool; inputs: {input name: "x" or "y"} (the
    program's spelling of each beam's input); reach: mm from each sensor to the crossing; noise: mm (one
    standard deviation of where an edge switches); hysteresis: mm; seed: the noise's."""

    def __init__(
        self,
        sensor2base: np.ndarray,
        pin: Pin,
        inputs: dict[str, str],
        reach: float = 100.0,
        range_mm: float = 200.0,
        noise: float = 0.0,
        hysteresis: float = 0.0,
        seed: int = 0,
    ) -> None:
        self.base2sensor = np.linalg.inv(sensor2base)
        self.pin, self.inputs, self.reach, self.range_mm = pin, dict(inputs), reach, range_mm
        self.noise, self.hysteresis = noise, hysteresis
        self.rng = np.random.default_rng(seed)
        self.switches = frozenset(inputs)
        self.state = dict.fromkeys(inputs, False)
        self.tcp2flange_inv = np.linalg.inv(pin.tcp2flange)

    def _beam(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        if self.inputs[name] == "x":
            return np.array([-self.reach, 0.0, 0.0]), np.array([1.0, 0.0, 0.0])
        return np.array([0.0, -self.reach, 0.0]), np.array([0.0, 1.0, 0.0])

    def meets(self, name: str, flange2base: np.ndarray, grow: float) -> bool:
        """Whether the beam meets the pin grown by `grow` mm (its radius and its end; negative: shrunk)."""
        tip, axis = self.pin.in_sensor(self.base2sensor @ flange2base)
        radius = self.pin.radius + grow
        if radius <= 0.0:
            return False
        origin, direction = self._beam(name)
        hit = entry_along(tip - grow * axis, axis, radius, self.pin.length + grow, origin, direction)
        return hit is not None and hit <= self.range_mm

    def on_wait(self, machine, where: str) -> bool:
        """The station acts only through its switching outputs (read at each cycle), never on a wait."""
        return False

    def switch(self, name: str, t: float, flange2base: np.ndarray | None) -> bool | None:
        """The output at one cycle (None: not this station's input); a pose unknown keeps the output."""
        if name not in self.switches:
            return None
        if flange2base is None:
            return self.state[name]
        jitter = self.rng.normal(0.0, self.noise) if self.noise > 0 else 0.0
        if self.state[name]:  # on: off once the pin has left the beam by hysteresis / 2
            self.state[name] = self.meets(name, flange2base, 0.5 * self.hysteresis + jitter)
        else:
            self.state[name] = self.meets(name, flange2base, -0.5 * self.hysteresis + jitter)
        return self.state[name]
