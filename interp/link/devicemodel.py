# SPDX-License-Identifier: Apache-2.0
"""A Python model of the controller as the link sees it, for the driver's tests: the
frame layer (sequence numbers, credits, coalesced replies, frame timeout), the register
file, the segment queue and a fake executor that takes one whole record every
1 / records_per_second seconds (lines and arcs move the position to their ends; the
switches and the probe are checked on lines only; a pause event holds, as
CONTROL.hold).  The same transport API as interp.link.simlink.SimLink:
write(bytes), read(size) honouring .timeout, in_waiting, now() (SIMULATED seconds:
time moves only while the host waits in read), close() -> dict.

Line noise: each bit of the 10-bit UART character (start, 8 data, stop) flips with
probability line_noise, both directions, seeded: a flipped stop bit loses the byte
(framing error), a flipped start bit loses it or, if a data bit reads as a start bit,
delivers a shifted byte.

Its CRC check is ideal: with line noise on, a frame the host never sent that passes
CRC-16 (about one corrupted frame in 65,536 does; a run at noise 0.01 corrupts
thousands) is counted in `crc_escapes` and refused as a bad CRC, so the driver's tests
test the driver, not that luck.  The controller has the real CRC-16 (docs/link-protocol.md).
"""
from __future__ import annotations

import math
import random
from collections import deque

from . import protocol as p
from ..gcode.compile import EVENT_CODES
from ..models.motion import to_machine
from .records import DEFAULT_BUILD, Build, Codes, RecordReader, decode, record_bytes
from .registers import field


PROBE_OVERSHOOT = 3         # steps the machine runs past the probe's touch while it stops
PAUSE_EVENT = EVENT_CODES["pause"]      # the event code of a program pause (M0, M6)


class DeviceModel:
    def __init__(self, *, build: Build = DEFAULT_BUILD, clock_hz: int = 50_000_000, baud: int = 115200,
                 line_noise: float = 0.0, seed: int = 1, queue_aw: int = 12, curves: bool = True,
                 records_per_second: float = 1000.0, frame_timeout: int = p.FRAME_TIMEOUT_BYTES,
                 fail_at: int | None = None, fail_code: int = 17, hold_seconds: float = 0.002,
                 switches: dict[int, tuple[str, int]] | None = None,
                 probe: tuple[int, str, int] | None = None, reset_at: float | None = None):
        # (reset_at: the controller resets at that simulated time, as at power-on or its board's
        # button: registers, queue, positions and frame layer start again; the line goes on)
        self._args = {k: v for k, v in locals().items() if k not in ("self", "reset_at")}
        self.reset_at = reset_at
        self.build, self.clock_hz, self.baud = build, int(clock_hz), baud
        self.byte_time = 10.0 / baud
        self.noise, self.rng = float(line_noise), random.Random(seed)
        self.queue_size, self.queue_aw, self.curves = 1 << queue_aw, queue_aw, curves
        self.record_time = 1.0 / records_per_second
        self.frame_timeout = frame_timeout * self.byte_time
        self.fail_at, self.fail_code, self.hold_seconds = fail_at, fail_code, hold_seconds
        self.record_len = record_bytes(build)
        self.timeout: float | None = None           # pyserial's attribute, seconds
        self.t = 0.0
        # host -> device: (arrival time, byte or None); device -> host likewise
        self.down: deque = deque()
        self.down_free = 0.0
        self.up: deque = deque()
        self.up_free = 0.0
        self.host_rx = bytearray()
        self._flip_in = self._next_flip()
        # frame layer
        self.parser = p.FrameParser()
        self.clean = p.FrameParser()                # the frames the host sent, before the noise
        self.sent_frames: set[tuple] = set()
        self.crc_escapes = 0
        self.last_rx = 0.0
        self.expected = 0
        self.pending_ack: tuple | None = None       # ("ACK",) or ("NAK", reason)
        self.pending_reply: tuple | None = None     # (seq, address)
        self.frames = self.duplicates = self.errors = self.gaps = 0
        # controller
        self.queue = bytearray()
        self.reader = RecordReader(build)           # plain and compact records
        self.executed: list[dict] = []              # every record the executor took, in order
        self.running_until = 0.0
        self.busy = False
        self.refused = False                        # STATUS.refused
        self.error = 0
        self.limits = 0
        self.position = [0, 0, 0]
        self.position_set = 0                       # STATUS.position_set
        # limit switches: axis -> ("min" | "max", steps): active at or beyond that position; a
        # line that reaches one stops there (ERROR 17), as the input guard gates the steps
        self.switches = dict(switches or {})
        # the probe: (axis, "min" | "max", steps), touching at or beyond that position (a touch
        # plate); armed (CONTROL.probe_arm), its touch latches PROBE_X/Y/Z and, with
        # CONTROL.probe_stop, holds the machine there
        self.probe = probe
        self.probe_armed = self.probe_stop = self.probe_valid = False
        self.probe_position = [0, 0, 0]
        self.hold = self.hold_moving = self.moving = False
        self.hold_since = 0.0
        self.enabled = False
        self.fill = False
        self.regs = {"OVERRIDE": 100, "PULSE_WIDTH": 25, "DIR_SETUP": 25, "DIR_HOLD": 25, "QUANTUM_LO": 1,
                     "QUANTUM_HI": 0, "MOTION": 2, "INPUT_INVERT": 0, "SPINDLE_PERIOD": clock_hz // 20000,
                     "OUTPUT_INVERT": 0, "INPUT_FILTER": 0x1F << 16,
                     "SPINDLE_OVERRIDE": 256, "LIMIT_SCALE": 0, "RATE_SCALE": 0}   # (its inputs are ideal: no filter delay)
        self.writes: list[tuple[str, int]] = []     # register writes executed, in order
        self.write_states: list[int] = []           # ... and the state each found

    # ---------------- transport API ----------------

    def now(self) -> float:
        return self.t

    @property
    def in_waiting(self) -> int:
        self._deliver()
        return len(self.host_rx)

    def write(self, data: bytes) -> int:
        if self.noise > 0:
            self.sent_frames.update((f.type, f.seq, f.payload) for f in self.clean.feed(bytes(data)))
        for byte in bytes(data):
            start = max(self.t, self.down_free)
            self.down_free = start + self.byte_time
            self.down.append((self.down_free, self._noisy(byte)))
        return len(data)

    def read(self, size: int = 1) -> bytes:
        deadline = math.inf if self.timeout is None else self.t + self.timeout
        while True:
            self._deliver()
            if len(self.host_rx) >= size:
                break
            step = self._next_event()
            if step is None or step > deadline:
                if deadline != math.inf:
                    self._run(deadline)
                    self.t = deadline
                self._deliver()
                break
            self._run(step)
            self.t = step
        out = bytes(self.host_rx[:size])
        del self.host_rx[:size]
        return out

    def reset_input_buffer(self) -> None:
        self._deliver()
        self.host_rx.clear()

    def close(self) -> dict:
        return {"seconds": self.t, "records": len(self.executed), "position": tuple(self.position),
                "frames": self.frames, "duplicates": self.duplicates, "errors": self.errors, "gaps": self.gaps,
                "crc_escapes": self.crc_escapes}

    # ---------------- the line ----------------

    def _next_flip(self) -> int:
        if self.noise <= 0:
            return 1 << 62
        if self.noise >= 1:
            return 0
        return int(math.log(1.0 - self.rng.random()) / math.log(1.0 - self.noise))

    def _noisy(self, byte: int) -> int | None:
        """One character through the noisy line: the byte received, or None (lost)."""
        if self._flip_in >= 10:
            self._flip_in -= 10
            return byte
        bits = [0] + [(byte >> n) & 1 for n in range(8)] + [1]
        while self._flip_in < 10:
            bits[self._flip_in] ^= 1
            self._flip_in += 1 + self._next_flip()
        self._flip_in -= 10
        if bits[0] == 1:                                  # no start bit here: a later 0 starts a byte
            try:
                at = bits.index(0, 1)
            except ValueError:
                return None
            bits = bits[at:] + [1] * 10
        if bits[9] != 1:                                  # framing error: the byte is dropped
            return None
        return sum(b << n for n, b in enumerate(bits[1:9]))

    def _deliver(self) -> None:
        while self.up and self.up[0][0] <= self.t:
            _, byte = self.up.popleft()
            if byte is not None:
                self.host_rx.append(byte)

    def power_cycle(self) -> None:
        """The controller's reset: everything but the line (bytes on it, the time) starts again."""
        line = {k: getattr(self, k) for k in ("t", "down", "down_free", "up", "up_free", "host_rx", "timeout",
                                             "rng", "_flip_in", "sent_frames", "clean", "crc_escapes")}
        self.__init__(**self._args)
        self.__dict__.update(line)

    def _next_event(self) -> float | None:
        times = []
        if self.reset_at is not None:
            times.append(max(self.reset_at, self.t))
        if self.down:
            times.append(self.down[0][0])
        if self.up:
            times.append(self.up[0][0])
        if self.parser.pending():
            times.append(self.last_rx + self.frame_timeout)
        if self._can_execute():
            times.append(max(self.running_until, self.t))
        elif self.busy:
            times.append(self.running_until)
        if self.hold and self.state() == p.HOLDING:
            times.append(self.hold_since + self.hold_seconds)
        times = [max(t, self.t) for t in times]
        return min(times) if times else None

    def _run(self, until: float) -> None:
        """Everything that happens up to `until` (in time order)."""
        while True:
            step = self._next_event()
            if step is None or step > until:
                return
            self.t = step
            if self.reset_at is not None and step >= self.reset_at:
                self.power_cycle()
                continue
            if self.down and self.down[0][0] <= step:
                when, byte = self.down.popleft()
                if self.parser.pending() and when - self.last_rx > self.frame_timeout:
                    self._frames(self.parser.expire(), truncated=True)
                self.last_rx = when
                if byte is not None:
                    self._frames(self.parser.feed(bytes([byte])))
            elif self.parser.pending() and step >= self.last_rx + self.frame_timeout:
                self._frames(self.parser.expire(), truncated=True)
            self._execute()
            self._transmit()
            self._deliver()
            if not self.down and not self.parser.pending() and step >= until:
                return

    # ---------------- the frame layer ----------------

    def _frames(self, frames, truncated: bool = False) -> None:
        bad = self.parser.bad_crc + self.parser.bad_len + self.parser.truncated
        if bad != getattr(self, "_bad_seen", 0):
            self._bad_seen = bad
            self.errors += 1
            self.pending_ack = ("NAK", p.NAK_CRC)
        for frame in frames:
            if self.noise > 0 and (frame.type, frame.seq, frame.payload) not in self.sent_frames:
                self.crc_escapes += 1               # corrupted, yet CRC-16 passes it: ideal check
                self.errors += 1
                self.pending_ack = ("NAK", p.NAK_CRC)
                continue
            self._frame(frame)
        self._transmit()

    def _frame(self, f: p.Frame) -> None:
        if f.type == p.HELLO:
            self.pending_ack = ("ACK",) if not f.payload else ("NAK", p.NAK_TYPE)
        elif f.type == p.READ:
            if len(f.payload) != 2:
                self.pending_ack = ("NAK", p.NAK_TYPE)
            else:
                self.pending_reply = (f.seq, int.from_bytes(f.payload, "little") & 0xFC)
        elif f.type in p.SEQUENCED:
            if (f.type == p.WRITE and len(f.payload) != 6) or (f.type == p.DATA and len(f.payload) > p.LMAX):
                self.pending_ack = ("NAK", p.NAK_TYPE)
                return
            d = (f.seq - self.expected) % 256
            if d >= 128:
                self.duplicates += 1
                self.pending_ack = ("ACK",)
            elif d:
                self.gaps += 1
                self.pending_ack = ("NAK", p.NAK_GAP)
            elif f.type == p.DATA and len(f.payload) > self.queue_size - len(self.queue):
                self.gaps += 1
                self.pending_ack = ("NAK", p.NAK_CREDIT)
            else:
                self.expected = (self.expected + 1) % 256
                self.frames += 1
                if f.type == p.DATA:
                    if not self.error:                      # in ALARM the bytes are taken and dropped
                        self.queue += f.payload
                    self._execute()
                else:
                    address, value = int.from_bytes(f.payload[:2], "little"), int.from_bytes(f.payload[2:], "little")
                    self.write_register(address & 0xFC, value)
                self.pending_ack = ("ACK",)
        else:
            self.pending_ack = ("NAK", p.NAK_TYPE)

    def _transmit(self) -> None:
        """Send the pending replies (REPLY first, then the ACK / NAK) when the line is free."""
        while self.up_free <= self.t and (self.pending_reply or self.pending_ack):
            if self.pending_reply:
                seq, address = self.pending_reply
                self.pending_reply = None
                frame = p.encode_frame(p.REPLY, seq, p.reply_payload(address, self.read_register(address)))
            else:
                kind = self.pending_ack
                self.pending_ack = None
                free = self.queue_size - len(self.queue)
                if kind[0] == "ACK":
                    frame = p.encode_frame(p.ACK, self.expected, p.ack_payload(free, self.state(), self.error))
                else:
                    frame = p.encode_frame(p.NAK, self.expected, p.nak_payload(kind[1], free))
            start = max(self.t, self.up_free)
            for n, byte in enumerate(frame):
                self.up.append((start + (n + 1) * self.byte_time, self._noisy(byte)))
            self.up_free = start + len(frame) * self.byte_time

    # ---------------- the controller ----------------

    def state(self) -> int:
        if self.error:
            return p.ALARM
        if self.hold:
            # a hold set while a record ran decelerates for hold_seconds; one at rest holds at once
            return p.HELD if self.t >= self.hold_since + self.hold_seconds or not self.hold_moving else p.HOLDING
        return p.RUN if self._busy() else p.IDLE

    def _busy(self) -> bool:
        """STATUS.busy: a record running or a whole one queued."""
        return self.busy or self._whole()

    def _whole(self) -> bool:
        """A whole record is in the queue."""
        size = self.reader.length(self.queue)
        return size is not None and len(self.queue) >= size

    def _can_execute(self) -> bool:
        return (not self.error and not self.hold and not self.fill and self._whole()
                and not (self.busy and self.running_until > self.t))

    def _execute(self) -> None:
        if self.busy and self.running_until <= self.t:
            self.busy = False
        while self._can_execute():
            size = self.reader.length(self.queue)
            raw = bytes(self.queue[:size])
            del self.queue[:size]
            motion = self.regs["MOTION"]                # the coded fields' scales
            self.reader.codes = Codes(field("MOTION.block_shift", motion), self.regs["LIMIT_SCALE"],
                                      field("MOTION.limit_shift", motion), self.regs["RATE_SCALE"],
                                      field("MOTION.rate_shift", motion))
            try:
                record = decode(self.reader.take(raw), self.build, strict=False)   # as the ports see it
            except ValueError:
                record = {"kind": 7}
            self.executed.append(record)
            n = len(self.executed)
            if record["kind"] >= 6:
                self.error = 18
            elif record["kind"] == 3 and not self.curves:
                self.error = 1
            elif record["kind"] in (1, 2) and record["plane"] == 3:
                self.error = 7
            elif self.fail_at is not None and n == self.fail_at:
                self.error = self.fail_code
                if self.fail_code == 17:
                    self.limits = 1
            if self.error:                          # ALARM flushes the queue and the bases
                self.busy = False
                self.queue.clear()
                self.reader = RecordReader(self.build)
                return
            if record["kind"] in (1, 2):            # an arc: from its start to its end (no switch or probe on the way)
                self._arc(record)
            if record["kind"] == 0 and self._line(record):
                self.busy = False
                self.queue.clear()
                self.reader = RecordReader(self.build)
                return
            self.busy, self.moving = True, record["kind"] < 4       # (a dwell or event does not move)
            self.running_until = self.t + self.record_time
            if record["kind"] == 5 and record["x"] & 0xFF == PAUSE_EVENT and not record["plane"] & 1:
                # a program pause (M0, M6): the controller sets CONTROL.hold itself, at rest
                self.hold, self.hold_since, self.hold_moving = True, self.t, False
                return

    def switch_active(self, axis: int) -> bool:
        if axis not in self.switches:
            return False
        side, at = self.switches[axis]
        return self.position[axis] <= at if side == "min" else self.position[axis] >= at

    def probe_touching(self) -> bool:
        if self.probe is None:
            return False
        axis, side, at = self.probe
        return self.position[axis] <= at if side == "min" else self.position[axis] >= at

    def probe_edge(self) -> tuple[int, str, int] | None:
        """The probe's active region as (axis, side, at): its touch, or with INPUT_INVERT's
        probe bit (G38.4, G38.5) the positions where it has lost contact (the model's probe
        closes its pin at the touch)."""
        if self.probe is None or not self.regs["INPUT_INVERT"] & p.PROBE_INPUT:
            return self.probe
        axis, side, at = self.probe
        return (axis, "max", at + 1) if side == "min" else (axis, "min", at - 1)

    def probe_active(self) -> bool:
        """INPUTS.probe: the touch, inverted by INPUT_INVERT's probe bit."""
        return self.probe_touching() != bool(self.regs["INPUT_INVERT"] & p.PROBE_INPUT)

    def _reach(self, delta, axis: int, side: str, at: int, active: bool):
        """The fraction of the line at which it reaches `at` on `axis` from outside, or None."""
        toward = delta[axis] < 0 if side == "min" else delta[axis] > 0
        if toward and not active and abs(at - self.position[axis]) <= abs(delta[axis]):
            return (at - self.position[axis]) / delta[axis]
        return None

    def _arc(self, record: dict) -> None:
        """Move to an arc record's end: (x, y) in its plane from the start, z along the plane's
        normal (motion_top's planes: XY, ZX, YZ)."""
        travel = to_machine(record["plane"], record["x"], record["y"], record["z"])
        self.position = [at + d for at, d in zip(self.position, travel)]

    def _line(self, record: dict) -> bool:
        """Move along a line record; True if a limit switch stopped it (position at the switch).
        The armed probe's touch latches the position there, and with probe_stop holds there."""
        delta = [record[name] for name in "xyz"]
        first = None                                # (fraction of the line, axis) of the first switch
        for axis, (side, at) in self.switches.items():
            fraction = self._reach(delta, axis, side, at, self.switch_active(axis))
            if fraction is not None:
                first = min(first or (2.0, 0), (fraction, axis))
        edge = self.probe_edge()
        touch = None if not self.probe_armed or edge is None else self._reach(delta, *edge, self.probe_active())
        if touch is not None and (first is None or touch < first[0]):
            axis = edge[0]
            at = [p + round(d * touch) for p, d in zip(self.position, delta)]
            at[axis] = edge[2]
            self.probe_position, self.probe_valid, self.probe_armed = at, True, False
            if self.probe_stop:                     # held just past the touch: the rest waits for an abort
                past = list(at)
                room = abs(self.position[axis] + delta[axis] - at[axis])
                past[axis] += (1 if delta[axis] > 0 else -1) * min(PROBE_OVERSHOOT, room)
                self.position, self.hold, self.hold_since, self.hold_moving = past, True, self.t, True
                return False
        if first is None:
            self.position = [p + d for p, d in zip(self.position, delta)]
            return False
        fraction, axis = first
        self.position = [p + round(d * fraction) for p, d in zip(self.position, delta)]
        self.position[axis] = self.switches[axis][1]
        self.error, self.limits = 17, self.limits | 1 << axis
        return True

    def read_register(self, address: int) -> int:
        b, a = self.build, p.REGISTER_ADDRESSES
        free = self.queue_size - len(self.queue)
        records = self.reader.whole_records(self.queue)
        values = {
            a["ID"]: p.ID_VALUE,
            a["VERSION"]: p.PROTOCOL_VERSION | self.record_len << 8 | b.W << 16 | b.POS_W << 24,
            a["BUILD0"]: b.FEED_W | b.FRAC << 8 | b.NW << 16 | b.PF << 24,
            a["BUILD1"]: b.LEN_W | b.ZW << 8 | b.MW << 16 | b.TW << 24,
            a["CLOCK_HZ"]: self.clock_hz,
            a["QUEUE_SIZE"]: (self.queue_size & 0xFFFF) | self.queue_aw << 16 | int(self.curves) << 24,
            a["STATUS"]: (self.state() | int(self._busy()) << 3 | int(self.state() == p.HELD) << 4
                          | int(self.enabled) << 6 | int(self.refused) * p.STATUS_REFUSED | min(records, 255) << 8
                          | int(self.probe_valid) * p.STATUS_PROBE_VALID | self.position_set << 16),
            a["ERROR"]: self.error | self.limits << 8,
            a["QUEUE_FREE"]: (free & 0xFFFF) | (free // self.record_len) << 16,
            a["POS_X"]: self.position[0] & 0xFFFFFFFF, a["POS_Y"]: self.position[1] & 0xFFFFFFFF,
            a["POS_Z"]: self.position[2] & 0xFFFFFFFF,
            a["INPUTS"]: (sum(int(self.switch_active(axis)) << (1 + axis) for axis in range(3))
                          | int(self.probe_active()) << 4),
            a["PROBE_X"]: self.probe_position[0] & 0xFFFFFFFF, a["PROBE_Y"]: self.probe_position[1] & 0xFFFFFFFF,
            a["PROBE_Z"]: self.probe_position[2] & 0xFFFFFFFF,
            a["CONTROL"]: (int(self.hold) | int(self.enabled) << 4 | int(self.fill) << 5
                           | int(self.probe_stop) * p.CONTROL_PROBE_STOP),
            a["LINK_FRAMES"]: (self.frames & 0xFFFF) | (self.duplicates & 0xFFFF) << 16,
            a["LINK_ERRORS"]: (self.errors & 0xFFFF) | (self.gaps & 0xFFFF) << 16,
            a["EXECUTED"]: len(self.executed) & 0xFFFFFFFF,
        }
        if address in values:
            return values[address]
        names = {v: k for k, v in a.items()}
        return self.regs.get(names.get(address, ""), 0)

    def write_register(self, address: int, value: int) -> None:
        names = {v: k for k, v in p.REGISTER_ADDRESSES.items()}
        name = names.get(address)
        if name is None:
            return
        self.writes.append((name, value))
        self.write_states.append(self.state())
        if name == "CONTROL":
            # an abort that cuts a record while the machine moves (not held at rest): ERROR 19
            at_speed = self.state() == p.HOLDING or (self.state() == p.RUN and self.busy and self.moving)
            if value & p.CONTROL_HOLD and not self.hold:
                self.hold_since, self.hold_moving = self.t, self.busy and self.moving
            self.hold = bool(value & p.CONTROL_HOLD)
            self.enabled = bool(value & p.CONTROL_ENABLE)
            self.probe_stop = bool(value & p.CONTROL_PROBE_STOP)
            if value & p.CONTROL_PROBE_ARM:
                self.probe_armed, self.probe_valid = True, False
            if value & p.CONTROL_CLEAR:                 # (a refusal in the same write wins)
                self.error, self.limits, self.refused = 0, 0, False
            rise = value & p.CONTROL_FILL and not self.fill and not value & p.CONTROL_ABORT
            if rise and self._busy():
                self.refused = True                 # fill would reset a running program
            else:
                self.fill = bool(value & p.CONTROL_FILL)    # records wait in the queue
            if value & p.CONTROL_ABORT:
                self.queue.clear()
                self.reader = RecordReader(self.build)
                self.busy = False
            if value & p.CONTROL_ABORT and at_speed and not self.error:
                self.error = p.ERROR_ABORT_AT_SPEED
            self._execute()
        elif name in p.SPEED_SETTINGS and self._busy():
            self.refused = True                     # taken only while not busy
        elif name in ("POS_X", "POS_Y", "POS_Z") and self._busy():
            self.refused = True
        elif name in ("POS_X", "POS_Y", "POS_Z"):
            axis, bits = "XYZ".index(name[-1]), self.build.POS_W
            low = value & ((1 << bits) - 1)
            new = low - (1 << bits) if low >> (bits - 1) else low
            if axis in self.switches:               # the switch stays where it is on the machine
                side, at = self.switches[axis]
                self.switches[axis] = (side, at + new - self.position[axis])
            self.position[axis] = new
            self.position_set |= 1 << axis
        elif name in self.regs:
            self.regs[name] = value & p.kept_bits(name) if name in p.PIN_SETTINGS else value
