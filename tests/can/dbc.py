"""A small reader of the DBC subset mbrt writes (BO_ and SG_ lines, Intel
byte order, factor and offset), written from the DBC format, not from
mbrt's code: the tests encode and decode frames with it to check that the
bridge's frames are what its DBC file says."""
import re

_MESSAGE = re.compile(r"^BO_ (\d+) (\w+): (\d+) (\w+)")
_SIGNAL = re.compile(r"^ SG_ (\w+) : (\d+)\|(\d+)@1([+-]) \(([^,]+),([^)]+)\)")


class Message:
    def __init__(self, frame_id, name, length):
        self.frame_id, self.name, self.length, self.signals = frame_id, name, length, []

    def decode(self, data):
        bits = int.from_bytes(bytes(data), "little")
        out = {}
        for name, start, size, signed, factor, offset in self.signals:
            raw = (bits >> start) & ((1 << size) - 1)
            if signed and raw >> (size - 1):
                raw -= 1 << size
            out[name] = (raw, raw * factor + offset)
        return out

    def encode(self, raw_values):
        """Frame bytes from raw signal values (integers)."""
        bits = 0
        for name, start, size, _, _, _ in self.signals:
            bits |= (raw_values[name] & ((1 << size) - 1)) << start
        return bits.to_bytes(self.length, "little")


def load(path):
    messages = {}
    current = None
    with open(path) as f:
        for line in f:
            m = _MESSAGE.match(line)
            if m:
                current = Message(int(m.group(1)), m.group(2), int(m.group(3)))
                messages[current.frame_id] = current
                continue
            s = _SIGNAL.match(line)
            if s and current is not None:
                current.signals.append((s.group(1), int(s.group(2)), int(s.group(3)), s.group(4) == "-",
                                        float(s.group(5)), float(s.group(6))))
    return messages
