"""How the PLC's part queue reaches a controller: registers, ranges of numbered signals, or named signal groups."""

from __future__ import annotations

from codegen.model.io import GROUP_BITS, OFFSET, SCALE, signal_name

# The queue's protocol (the same on every controller): the part's number (seq), the encoder's count when
# the camera saw it (count), where it lies across the belt (x) and its top (z), and the line's cycle stop;
# the program takes a part by writing its number back (ack). Registers carry x and z as floats in mm
# (a [program.<kind>] table's names); groups of digital inputs (its signals) carry x, z and the encoder's live
# count (codegen.model.io GROUP_BITS, OFFSET, SCALE).


def encode_mm(value: float) -> int:
    return round(SCALE * value) + OFFSET


class RegisterBus:
    """Registers the device writes and reads by name (the table's names); the PLC's counter now is a live
    register (its count at the reading's moment). The controller's own encoder input (the device's
    encoder()) counts the same belt from another zero: it serves the tracking only."""

    def __init__(self, names: dict) -> None:
        self.names = names

    def present(self, machine, values: dict) -> None:
        for key in ("count", "x", "z", "seq"):
            machine.write_variable(self.names[key], values[key])

    def ack(self, machine):
        return machine.read_variable(self.names["ack"])

    def stop(self, machine) -> None:
        machine.write_variable(self.names["stop"], True)

    def live(self, belt, name: str, t: float):
        return belt.count(t) if name == self.names["encoder"] else None


class BitBus:
    """Each role a range [first, last] of numbered inputs (the ack of outputs), least significant bit
    first; the stop a single input; the encoder's current count live on its range. input_name and
    output_name: the controller's name of signal n (codegen/model/io.py signal_name)."""

    def __init__(self, signals: dict, input_name, output_name) -> None:
        self.signals, self.input_name, self.output_name = signals, input_name, output_name
        first, last = signals["encoder"]
        self._encoder = {input_name(n): bit for bit, n in enumerate(range(first, last + 1))}

    def _set(self, machine, role: str, value: int) -> None:
        first, last = self.signals[role]
        for bit, n in enumerate(range(first, last + 1)):
            machine.signals[self.input_name(n)] = bool((value >> bit) & 1)

    def present(self, machine, values: dict) -> None:
        self._set(machine, "count", values["count"])
        self._set(machine, "x", encode_mm(values["x"]))
        self._set(machine, "z", encode_mm(values["z"]))
        self._set(machine, "seq", values["seq"] % 2**GROUP_BITS)

    def ack(self, machine) -> int:
        first, last = self.signals["ack"]
        bits = enumerate(range(first, last + 1))
        return sum(int(machine.signals.get(self.output_name(n), False)) << bit for bit, n in bits)

    def stop(self, machine) -> None:
        machine.signals[self.input_name(self.signals["stop"])] = True

    def live(self, belt, name: str, t: float):
        bit = self._encoder.get(name)
        return None if bit is None else bool((belt.count(t) >> bit) & 1)


class NamedBus:
    """Each role a named signal of the controller's I/O configuration: groups of inputs, the ack a group
    of outputs, the stop a digital input; the encoder's group live."""

    def __init__(self, signals: dict) -> None:
        self.signals = signals

    def present(self, machine, values: dict) -> None:
        s = self.signals
        machine.signals[s["count"]] = values["count"]
        machine.signals[s["x"]] = encode_mm(values["x"])
        machine.signals[s["z"]] = encode_mm(values["z"])
        machine.signals[s["seq"]] = values["seq"] % 2**GROUP_BITS

    def ack(self, machine):
        return machine.outputs.get(self.signals["ack"], 0)

    def stop(self, machine) -> None:
        machine.signals[self.signals["stop"]] = True

    def live(self, belt, name: str, t: float):
        return belt.count(t) if name == self.signals["encoder"] else None


def bus_for(target, queue: dict):
    """The target's bus from the queue's facts (names: registers; signals: ranges of numbered signals or
    names)."""
    names = queue.get("names")
    if names is not None:
        return RegisterBus(names)
    signals = queue["signals"]
    if not isinstance(signals["seq"], list):
        return NamedBus(signals)
    return BitBus(signals, lambda n: signal_name(target, "input", n), lambda n: signal_name(target, "output", n))
