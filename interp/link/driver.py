# SPDX-License-Identifier: Apache-2.0
"""The host's sender (docs/host-driver.md): connect (HELLO, the build check, the machine
settings), the record stream in DATA frames (a window of at most 16 unacknowledged
sequenced frames, credits from the ACKs' free bytes, go-back-N after NAK 1 / 2 / 3 or a
retransmission timeout, DATA payloads that shrink after errors and grow back after
successes), register reads and writes, the progress poll, hold / resume / abort.

The transport is pyserial-like (write, read honouring .timeout); the driver's clock is
`transport.now` when it has one (the simulators: link time), else time.monotonic.

Go-back-N: after an error the driver lets the line go quiet (everything it wrote has
left, the replies have come back), asks HELLO for the controller's next expected
sequence number E, and re-sends from E, re-cut into the (smaller) payload size.  Since
nothing of the old frames can still arrive, a re-cut frame never meets an old one
with the same sequence number.
"""
from __future__ import annotations

import time
from collections import deque
from dataclasses import dataclass, field
from typing import ClassVar

from . import protocol as p
from ..models.speed_ramp import BLOCK_SHIFT_MIN
from .records import DEFAULT_BUILD, Build, Codes, record_bytes
from .registers import compose

REG = p.REGISTER_ADDRESSES
MAX_REFUSALS = 8            # NAK 4 in a row without progress before the driver gives up


class LinkError(Exception):
    """The link failed (no answer, too many errors): exit status 1."""


class MismatchError(Exception):
    """The controller's build or clock is not the one the program was compiled for: exit 2."""


class MachineError(Exception):
    """The controller latched an error (ALARM)."""

    def __init__(self, code: int, limits: int, executed: int, message: str):
        super().__init__(message)
        self.code, self.limits, self.executed = code, limits, executed


@dataclass
class Item:
    """One sequenced frame: DATA (a slice of the record stream) or WRITE."""

    type: int
    payload: bytes
    offset: int = 0             # DATA: where its bytes start in the stream
    write_id: int = -1          # WRITE: its number (write_register waits for it)
    after: int = 0              # WRITE: the stream bytes cut before it was queued, which go first


@dataclass
class Snapshot:
    """What the progress display shows (from the latest polls)."""

    executed: int = 0           # records dispatched to the cores since connect
    records: int = 0            # records of the program
    acked_bytes: int = 0
    total_bytes: int = 0
    state: int = 0
    queue_records: int = 0
    position: list = field(default_factory=lambda: [0, 0, 0])
    error: int = 0
    override: int = 100         # the feed override in force, percent
    spindle: int = 100          # the spindle override in force, percent


# Feed override keys: '+' (or '=', the same key unshifted) and '-' by 10 %, '>' '<' by 1 %
# within Grbl's 10 .. 200 %; as in LinuxCNC's Axis, '1' .. '9' set 10 .. 90 % and '0' 100 %
OVERRIDE_STEPS = {"+": 10, "=": 10, "-": -10, ">": 1, "<": -1}
OVERRIDE_SETS = {str(n): 10 * n for n in range(1, 10)} | {"0": 100}
OVERRIDE_MIN, OVERRIDE_MAX = 10, 200
# Spindle override keys (Grbl's spindle override, 10 .. 200 % as well): ']' '[' by 10 %,
# '}' '{' by 1 %, '\' 100 %
SPINDLE_STEPS = {"]": 10, "[": -10, "}": 1, "{": -1}
SPINDLE_SETS = {"\\": 100}


@dataclass
class FeedOverride:
    """The feed override the keys set, in percent of the programmed feed; kept across the
    runs of one program (its pieces around probe moves)."""

    percent: int = 100
    set: bool = False           # a key has set it (until then the run's settings hold)
    STEPS: ClassVar[dict] = OVERRIDE_STEPS
    SETS: ClassVar[dict] = OVERRIDE_SETS

    def takes(self, key: str) -> bool:
        return key in self.STEPS or key in self.SETS

    def after(self, key: str) -> int:
        """The percent after `key` (STEPS, SETS), within 10 .. 200."""
        if key in self.SETS:
            return self.SETS[key]
        return min(OVERRIDE_MAX, max(OVERRIDE_MIN, self.percent + self.STEPS.get(key, 0)))

    def press(self, key: str) -> bool:
        """Take `key`: True if it changed the percent (which is then `set`)."""
        percent = self.after(key)
        if percent == self.percent:
            return False
        self.percent, self.set = percent, True
        return True


@dataclass
class SpindleOverride(FeedOverride):
    """The spindle override the keys set, in percent of the programmed spindle speed or laser
    power (SPINDLE_OVERRIDE, as spindle_scale); kept across the runs of one program."""

    STEPS: ClassVar[dict] = SPINDLE_STEPS
    SETS: ClassVar[dict] = SPINDLE_SETS


def spindle_scale(percent: float) -> int:
    """SPINDLE_OVERRIDE's scale for a percent: 256 is 100 %."""
    return round(percent * 256 / 100)


class Driver:
    def __init__(self, transport, *, baud: int = 115200, window: int = 16, lmax: int = p.LMAX,
                 min_payload: int = 8, margin: float | None = None, dead_seconds: float = 2.0,
                 poll_seconds: float = 0.05, grow_after: int = 2):
        self.transport = transport
        self.clock = getattr(transport, "now", time.monotonic)
        if margin is None:          # reply latency beyond the bytes' time: a USB serial port's, or none (simulators)
            margin = 0.002 if hasattr(transport, "now") else 0.03
        self.byte_time = 10.0 / baud
        self.window, self.lmax, self.min_payload = window, lmax, min_payload
        self.margin, self.dead_seconds, self.poll_seconds = margin, dead_seconds, poll_seconds
        self.grow_after = grow_after
        self.transport.timeout = max(0.002, 4 * self.byte_time)
        self.parser = p.FrameParser()
        # sequenced frames: outstanding[0] has the absolute sequence number `base` (= E known)
        self.base = 0
        self.outstanding: deque[Item] = deque()
        self.sent = 0                   # outstanding[:sent] have been sent
        self.stream = b""
        self.stream_pos = 0             # stream bytes cut into items
        self.acked_bytes = 0
        self.write_queue: deque[Item] = deque()
        self.writes_issued = self.writes_done = 0
        self.free = 0                   # the latest ACK's free bytes
        self.payload = lmax
        self.streak = 0
        self.progress_time = 0.0
        self.line_free = 0.0            # when the bytes written so far have left
        self.last_valid = self.clock()
        self.device_state = self.device_error = 0
        # register reads
        self.read_tag = 0
        self.read_pending: tuple | None = None     # (tag, address, deadline)
        self.read_wanted: deque[int] = deque()
        self.values: dict[int, int] = {}
        self.fresh: set[int] = set()
        # counters
        self.frames_sent = self.recoveries = self.naks = self.timeouts = self.refusals = 0
        self._waiting = False
        self.next_probe = 0.0

    # ---------------- low level ----------------

    def _write(self, frame: bytes) -> None:
        now = self.clock()
        self.transport.write(frame)
        self.line_free = max(now, self.line_free) + len(frame) * self.byte_time

    def _check_dead(self) -> None:
        if self.clock() - self.last_valid > self.dead_seconds:
            if not (self.sent or self.read_pending or self.parser.pending() or self._waiting):
                self.last_valid = self.clock()          # nothing was asked: silence is fine
                return
            raise LinkError(f"no valid frame from the controller for {self.dead_seconds:g} s "
                            f"({self.recoveries} retransmissions)")

    def _receive(self) -> list:
        data = self.transport.read(256)
        frames = self.parser.feed(data) if data else []
        if not data and self.parser.pending():
            frames = self.parser.expire()
        out = []
        for frame in frames:
            try:
                reply = p.decode_reply(frame)
            except ValueError:
                continue                    # not a controller frame (an echo, noise that passed the CRC)
            self.last_valid = self.clock()
            out.append(reply)
        return out

    def _advance(self, wire_seq: int, free: int) -> bool:
        """An ACK / NAK says E = wire_seq: drop the frames it acknowledges."""
        d = (wire_seq - self.base) % 256
        if d > self.sent:
            return False                    # older than what we know, or not ours
        for _ in range(d):
            item = self.outstanding.popleft()
            if item.type == p.DATA:
                self.acked_bytes += len(item.payload)
            else:
                self.writes_done = max(self.writes_done, item.write_id + 1)
        self.base += d
        self.sent -= d
        self.free = free
        if d:
            self.refusals = 0
            self.progress_time = self.clock()
            self.streak += d
            if self.streak >= self.grow_after and self.payload < self.lmax:
                self.payload = min(self.lmax, self.payload + max(2, self.payload // 4))
                self.streak = 0
        return True

    def _handle(self, reply, recovering: bool = False) -> str | None:
        """One controller frame; 'error' when it asks for a go-back."""
        if isinstance(reply, p.Reply):
            if self.read_pending and reply.seq == self.read_pending[0] and reply.address == self.read_pending[1]:
                self.values[reply.address] = reply.value
                self.fresh.add(reply.address)
                self.read_pending = None
            return None
        if isinstance(reply, p.Ack):
            if self._advance(reply.seq, reply.free):
                self.device_state, self.device_error = reply.state, reply.error
                self._waiting = False
            elif not self.sent:
                # nothing in flight, so every ACK of ours came before and E can only be base (the
                # credit probe's answer): the controller lost its state
                raise LinkError(f"the controller expects frame {reply.seq}, the driver {self.base % 256}: "
                                "was it reset? (its queue and position are lost)")
            return None
        self.naks += 1
        if self._advance(reply.seq, reply.free) and reply.reason == p.NAK_TYPE:
            # a frame that passed the CRC but that the controller cannot take: a host bug (or, very
            # rarely, a CRC collision on a noisy line): go back, and give up if it keeps coming
            self.refusals += 1
            if self.refusals > MAX_REFUSALS:
                raise LinkError(f"the controller refused a frame {self.refusals} times: "
                                f"{p.NAK_TEXT[p.NAK_TYPE]} (a protocol mismatch)")
        if not recovering and self.sent and reply.reason in (p.NAK_CRC, p.NAK_GAP, p.NAK_TYPE):
            return "error"
        if not recovering and self.sent and reply.reason == p.NAK_CREDIT:
            return "credit"                 # the line is fine: resend when the credit allows, same size
        return None

    def _rto(self) -> float:
        in_flight = self._in_flight()
        backlog = max(0.0, self.line_free - self.clock())
        return backlog + (in_flight + 40) * self.byte_time + self.margin

    def _in_flight(self) -> int:
        return sum(len(i.payload) + p.OVERHEAD for i in list(self.outstanding)[:self.sent])

    def _flight_limit(self) -> int:
        """Bytes in flight that keep the line busy for a round trip (two frames, the ACK,
        the latency): more would only be lost after an error (go-back-N)."""
        return 2 * (self.payload + p.OVERHEAD) + 40 + int(self.margin / self.byte_time)

    def _credit(self) -> int:
        return self.free - sum(len(i.payload) for i in list(self.outstanding)[:self.sent] if i.type == p.DATA)

    def _next_item(self) -> Item | None:
        # a WRITE goes after the stream bytes cut before it was queued, also when a go-back
        # cuts them again (the fill release after the fill, a resume after the data before it)
        if self.write_queue and self.write_queue[0].after <= self.stream_pos:
            return self.write_queue.popleft()
        left = (self.write_queue[0].after if self.write_queue else len(self.stream)) - self.stream_pos
        if left <= 0:
            return None
        credit = self._credit() - sum(len(i.payload) for i in list(self.outstanding)[self.sent:]
                                      if i.type == p.DATA)
        size = min(self.payload, left, credit)
        if size < min(self.payload, left, 16):
            return None                     # wait for credit
        item = Item(p.DATA, self.stream[self.stream_pos:self.stream_pos + size], offset=self.stream_pos)
        self.stream_pos += size
        return item

    def _send_some(self) -> None:
        while self.sent < self.window:
            if self.sent == len(self.outstanding):
                item = self._next_item()
                if item is None:
                    break
                self.outstanding.append(item)
            item = self.outstanding[self.sent]
            if item.type == p.DATA and len(item.payload) > self._credit():
                break
            if self.sent and self._in_flight() + len(item.payload) + p.OVERHEAD > self._flight_limit():
                break                       # enough to keep the line busy until the ACKs come
            if self.sent == 0:
                self.progress_time = self.clock()
            self._write(p.encode_frame(item.type, (self.base + self.sent) % 256, item.payload))
            self.sent += 1
            self.frames_sent += 1

    def _poll_reads(self) -> None:
        now = self.clock()
        if self.read_pending and now > self.read_pending[2]:
            self.read_wanted.appendleft(self.read_pending[1])      # lost: ask again
            self.read_pending = None
        if self.read_pending is None and self.read_wanted:
            address = self.read_wanted.popleft()
            self.read_tag = (self.read_tag + 1) % 256
            self._write(p.encode_frame(p.READ, self.read_tag, p.read_payload(address)))
            deadline = self.line_free + 30 * self.byte_time + self.margin
            self.read_pending = (self.read_tag, address, deadline)

    def pump(self) -> None:
        """Send what the window and credit allow, read the replies, recover from errors."""
        self._send_some()
        self._poll_reads()
        error = credit = False
        for reply in self._receive():
            answer = self._handle(reply)
            error = answer == "error" or error
            credit = answer == "credit" or credit
        now = self.clock()
        if (not self.sent and self.stream_pos < len(self.stream) and now >= self.next_probe
                and self.read_pending is None):
            # waiting for credit with nothing in flight: no ACK would come, ask for one
            self._write(p.encode_frame(p.HELLO, 0))
            self.next_probe = self.line_free + 30 * self.byte_time + self.margin
            self._waiting = True
        elif self.sent or self.stream_pos >= len(self.stream):
            self._waiting = False
        if not error and self.sent and now - self.progress_time > self._rto():
            self.timeouts += 1
            error = True
        if error or credit:
            self.recover(shrink=error)
        self._check_dead()

    def recover(self, shrink: bool = True) -> None:
        """Go back N: wait until the line is quiet, learn E with HELLO, re-cut what is not
        acknowledged (into smaller frames after a line error; NAK 3 keeps the size)."""
        self.recoveries += 1
        if shrink:
            self.payload = max(self.min_payload, self.payload * 3 // 4)
        self.streak = 0
        quiet = max(self.clock(), self.line_free) + 40 * self.byte_time + self.margin
        while self.clock() < quiet:
            for reply in self._receive():
                self._handle(reply, recovering=True)
            self._check_dead()
        if self.read_pending:                   # its REPLY may have been lost in the noise: ask again
            self.read_wanted.appendleft(self.read_pending[1])
            self.read_pending = None
        self.parser.expire()
        self._waiting = True
        try:
            self._hello(recovering=True)
        finally:
            self._waiting = False
        # everything not acknowledged goes back to be cut again
        data = [i for i in self.outstanding if i.type == p.DATA]
        writes = [i for i in self.outstanding if i.type == p.WRITE]
        if data:
            self.stream_pos = data[0].offset
        self.write_queue.extendleft(reversed(writes))
        self.outstanding.clear()
        self.sent = 0

    def _hello(self, recovering: bool = False) -> p.Ack | p.Nak:
        """HELLO until an ACK (or NAK) tells E and the free bytes."""
        while True:
            self._write(p.encode_frame(p.HELLO, 0))
            deadline = self.line_free + 30 * self.byte_time + self.margin
            while self.clock() < deadline:
                for reply in self._receive():
                    if not isinstance(reply, (p.Ack, p.Nak)):
                        self._handle(reply, recovering=True)
                        continue
                    if not recovering:
                        self.base, self.free = reply.seq, reply.free      # connect: E starts the sequence
                    elif not self._advance(reply.seq, reply.free):
                        # the line is quiet, so E is between base and base + sent unless the
                        # controller lost its state: it would take nothing from us again
                        raise LinkError(f"the controller expects frame {reply.seq}, the driver "
                                        f"{self.base % 256} .. {(self.base + self.sent) % 256}: "
                                        "was it reset? (its queue and position are lost)")
                    if isinstance(reply, p.Ack):
                        self.device_state, self.device_error = reply.state, reply.error
                    return reply
                self._check_dead()

    # ---------------- register access ----------------

    def connect(self) -> None:
        self.parser.expire()
        self.last_valid = self.clock()
        self._waiting = True
        try:
            self._hello()
        finally:
            self._waiting = False

    def read_register(self, name_or_address) -> int:
        address = REG[name_or_address] if isinstance(name_or_address, str) else name_or_address
        self.fresh.discard(address)
        if address not in self.read_wanted:
            self.read_wanted.append(address)
        while address not in self.fresh:
            self.pump()
        return self.values[address]

    def queue_write(self, name_or_address, value: int) -> int:
        address = REG[name_or_address] if isinstance(name_or_address, str) else name_or_address
        item = Item(p.WRITE, p.write_payload(address, value), write_id=self.writes_issued, after=self.stream_pos)
        self.writes_issued += 1
        self.write_queue.append(item)
        return item.write_id

    def write_register(self, name_or_address, value: int) -> None:
        wid = self.queue_write(name_or_address, value)
        while self.writes_done <= wid:
            self.pump()

    # ---------------- the stream ----------------

    def start_stream(self, data: bytes) -> None:
        self.stream, self.stream_pos, self.acked_bytes = bytes(data), 0, 0
        for item in self.write_queue:           # queued before this stream: they go first
            item.after = 0

    def stream_done(self) -> bool:
        return self.stream_pos >= len(self.stream) and not self.outstanding and not self.write_queue

    def drop_stream(self) -> None:
        """Send no more records (abort): the unsent part of the stream and unsent frames go."""
        keep = deque(list(self.outstanding)[:self.sent])
        keep += [i for i in list(self.outstanding)[self.sent:] if i.type == p.WRITE]
        self.outstanding = keep
        self.stream = self.stream[:self.stream_pos]

    def poll(self, names) -> None:
        for name in names:
            if REG[name] not in self.read_wanted and not (self.read_pending and self.read_pending[1] == REG[name]):
                self.read_wanted.append(REG[name])


# ---------------- the session: connect, check, configure, run ----------------

def field(value: int, lsb: int, width: int) -> int:
    return (value >> lsb) & ((1 << width) - 1)


def check_controller(driver: Driver, build: Build = DEFAULT_BUILD, clock_hz: float | None = None,
                     curves: bool = False) -> dict[str, int]:
    """Read ID, VERSION, BUILD0, BUILD1, CLOCK_HZ, QUEUE_SIZE; MismatchError (one line) when the
    controller is not the build the program was compiled for."""
    v = {name: driver.read_register(name) for name in ("ID", "VERSION", "BUILD0", "BUILD1", "CLOCK_HZ",
                                                         "QUEUE_SIZE")}
    if v["ID"] != p.ID_VALUE:
        raise MismatchError(f"not an interp controller (ID 0x{v['ID']:08X}, expected 0x{p.ID_VALUE:08X})")
    got = {"protocol": field(v["VERSION"], 0, 8), "record bytes": field(v["VERSION"], 8, 8),
           "W": field(v["VERSION"], 16, 8), "POS_W": field(v["VERSION"], 24, 8),
           "FEED_W": field(v["BUILD0"], 0, 8), "FRAC": field(v["BUILD0"], 8, 8), "NW": field(v["BUILD0"], 16, 8),
           "PF": field(v["BUILD0"], 24, 8), "LEN_W": field(v["BUILD1"], 0, 8), "ZW": field(v["BUILD1"], 8, 8),
           "MW": field(v["BUILD1"], 16, 8), "TW": field(v["BUILD1"], 24, 8)}
    want = {"protocol": p.PROTOCOL_VERSION, "record bytes": record_bytes(build), "W": build.W,
            "POS_W": build.POS_W, "FEED_W": build.FEED_W, "FRAC": build.FRAC, "NW": build.NW, "PF": build.PF,
            "LEN_W": build.LEN_W, "ZW": build.ZW, "MW": build.MW}
    bad = [f"{k} {got[k]} (the program needs {want[k]})" for k in want if got[k] != want[k]]
    if bad:
        raise MismatchError(f"the controller's build differs: {', '.join(bad)}")
    if clock_hz is not None and v["CLOCK_HZ"] != round(clock_hz):
        raise MismatchError(f"the controller's clock is {v['CLOCK_HZ']} Hz, the machine file's clock_hz is "
                            f"{clock_hz:g} Hz: give --machine with the board's clock (boards/<board>/machine.toml)")
    if curves and not field(v["QUEUE_SIZE"], 24, 1):
        raise MismatchError("the program has curve commands and the controller is built without CURVES")
    return v


def settings_writes(timing: dict, settings: dict, codes=None) -> list[tuple[str, int]]:
    """The register writes of the machine settings `interp gcode` runs with (step timing,
    speed quantum, profile shifts, feed override; the spindle override at 100 %) and of the
    record codes' scales (`codes`: a compiled program's, see records.Codes.of; none: 0), in
    order: for a driver, a bench or firmware."""
    quantum = int(settings.get("speed_quantum", 1))
    c = Codes.of(codes) or Codes()
    motion = compose("MOTION", block_shift=int(settings.get("block_shift", BLOCK_SHIFT_MIN)),
                     jerk_shift=int(settings.get("jerk_shift", 0)), limit_shift=c.limit_shift, rate_shift=c.rate_shift)
    return [("PULSE_WIDTH", int(timing["pulse_width"])), ("DIR_SETUP", int(timing["setup"])),
            ("DIR_HOLD", int(timing["hold"])), ("QUANTUM_LO", quantum & 0xFFFFFFFF), ("QUANTUM_HI", quantum >> 32),
            ("MOTION", motion), ("LIMIT_SCALE", c.limit_scale), ("RATE_SCALE", c.rate_scale),
            ("OVERRIDE", int(settings.get("override", 100))), ("SPINDLE_OVERRIDE", spindle_scale(100))]


PIN_SETTINGS = p.PIN_SETTINGS
CONTROL_KEPT = p.kept_bits("CONTROL")           # hold, enable, fill, probe_stop (not the strobes)


def same_pin_setting(name: str, have: int, want: int) -> bool:
    """Whether the controller's value of a pin setting register is the machine file's: an
    INPUT_FILTER with period 0 is off whatever its mask (a bitstream from before the
    register reads 0 there)."""
    if name == "INPUT_FILTER" and not have & 0xFFFF and not want & 0xFFFF:
        return True
    return have == want


def apply_pin_settings(driver: Driver, settings: dict[str, int]) -> None:
    """Write INPUT_INVERT, INPUT_FILTER, OUTPUT_INVERT and SPINDLE_PERIOD (the machine file's
    input.invert, input.filter_us and input.unfiltered, output.invert, spindle.pwm_hz) where the
    controller's differ (after its reset: the build's INPUT_INVERT_RESET and OUTPUT_INVERT_RESET,
    0 by default; no filter; 20 kHz).  A name left out of
    `settings` is not written.  Call it at rest (check_idle), before reading ERROR.
      * OUTPUT_INVERT is written with the drivers disabled (CONTROL.enable 0, then restored):
        a changed step bit makes an edge on its pin.
      * An e-stop error (16) latched under another e-stop polarity, or a limit error (17) whose
        switches all had another polarity, came from the polarity, not the machine (a
        normally-open switch reads active until then): it is cleared if those inputs read
        inactive now.  Any other error stays.
    LinkError if the controller does not take a value (a bitstream older than the register)."""
    masks = {name: p.kept_bits(name) for name in PIN_SETTINGS if name in settings}
    before = {name: driver.read_register(name) & mask for name, mask in masks.items()}
    for name, mask in masks.items():
        value = settings[name] & mask
        if same_pin_setting(name, before[name], value):
            continue
        control = driver.read_register("CONTROL") & CONTROL_KEPT
        off = name == "OUTPUT_INVERT" and control & p.CONTROL_ENABLE
        if off:
            driver.write_register("CONTROL", control & ~p.CONTROL_ENABLE)
        driver.write_register(name, value)
        if off:
            driver.write_register("CONTROL", control)
        if driver.read_register(name) & mask != value:
            raise LinkError(f"the controller did not take {name} = 0x{value:X} (a bitstream without it: "
                            "build and load the current one)")
    changed = before["INPUT_INVERT"] ^ (settings["INPUT_INVERT"] & masks["INPUT_INVERT"]) if "INPUT_INVERT" in masks else 0
    if not changed:
        return
    error, inputs = driver.read_register("ERROR"), driver.read_register("INPUTS")
    code, limits = error & 0xFF, error >> 8 & 7
    if (code == 16 and changed & 1 and not inputs & 1) or \
            (code == 17 and limits and (changed >> 1) & limits == limits and not (inputs >> 1) & limits):
        driver.write_register("CONTROL", (driver.read_register("CONTROL") & CONTROL_KEPT) | p.CONTROL_CLEAR)


POSITION = ("POS_X", "POS_Y", "POS_Z")
RESET_TEXT = "the controller was reset during the run: its queue and position are lost"
STOP_SECONDS = 10.0         # Ctrl-X: the longest wait for the feed hold before the abort
AT_SPEED = "the motors may have lost steps"


def signed32(value: int) -> int:
    return value - (1 << 32) if value >> 31 else value


def read_position(driver: Driver) -> tuple[int, int, int]:
    """POS_X/Y/Z: the machine's position in steps, the step pulses counted since the
    controller's reset (an abort or an alarm keeps it)."""
    return tuple(signed32(driver.read_register(name)) for name in POSITION)


def check_idle(driver: Driver) -> None:
    """LinkError when the controller is busy with a program (ALARM is not busy: an abort
    flushes it)."""
    status = driver.read_register("STATUS")
    if field(status, 3, 1) and field(status, 0, 3) != p.ALARM:
        raise LinkError(f"the controller is busy ({p.STATE_NAMES.get(field(status, 0, 3), '?')}): "
                        "wait for its program to end or abort it")


def configure(driver: Driver, timing: dict, settings: dict, codes=None) -> None:
    """The machine settings `interp gcode` runs with and the record codes' scales, written
    through the link.  The controller takes the speed settings (QUANTUM, MOTION, the
    scales) only while it is not busy (ALARM is not: it flushes): LinkError when it is busy
    with a program, or did not take them."""
    check_idle(driver)
    writes = settings_writes(timing, settings, codes)
    for name, value in writes:
        driver.write_register(name, value)
    for name, value in writes:
        if name in p.SPEED_SETTINGS and driver.read_register(name) != value:
            raise LinkError(f"the controller did not take {name} (it became busy: send again when it is idle; "
                            "or a bitstream without it: build and load the current one)")


POLLED = ("EXECUTED", "QUEUE_FREE", *POSITION, "ERROR", "STATUS")   # STATUS after EXECUTED: the end test


@dataclass
class Outcome:
    status: str                 # "done", "aborted", "error"
    executed: int
    seconds: float
    error: int = 0
    limits: int = 0
    message: str = ""


def run_program(driver: Driver, stream: bytes, records: int, *, progress=None, keys=None,
                max_seconds: float | None = None, pause_resume: float | None = 0.0,
                on_pause=None, at_pause=None, probe: bool = False, override: FeedOverride | None = None,
                spindle: SpindleOverride | None = None) -> Outcome:
    """Stream the records and follow the run to its end: all records executed and the
    controller not busy.  progress(Snapshot) after every poll round; keys() -> the keys
    typed since the last call ('!' hold, '~' resume, Ctrl-X stop; with `override`, the
    feed override keys of OVERRIDE_STEPS and OVERRIDE_SETS: OVERRIDE at once, except in a
    probe move, which runs at 100 % as in Grbl and takes the keys' percent when it ends; with
    `spindle`, the spindle override keys of SPINDLE_STEPS and SPINDLE_SETS: SPINDLE_OVERRIDE
    at once).
    Ctrl-X stops as a sender keeps the position: nothing more is sent, a feed hold brings the machine to
    rest on its path, then CONTROL.abort flushes the queue (within STOP_SECONDS in any
    case); a second Ctrl-X aborts at once (at speed the motors may lose steps that the
    position counters have counted).
    A program pause (M0, M1, M6: the controller holds by itself) is released
    pause_resume seconds after the machine has stopped, or, with None, by the '~' key;
    on_pause(Snapshot) is told once per pause.  A hold by '!' in the moment the controller
    paused by itself looks like the user's: at_pause(Snapshot) -> True says the held machine
    stands where a pause not told yet runs, so it is told as the program's pause (and one '~'
    releases both).
    The run starts from a filled queue: CONTROL.fill is set while the first bytes go out
    (the whole program, or all but LMAX bytes of the queue's room) and cleared by a
    WRITE sequenced after them, so motion_top starts as from a reset with its records
    there: the steps come at the cycles `interp gcode` gives while the link keeps up.
    probe (a G38.2 .. G38.5 move): the probe is armed with CONTROL.probe_stop, so its touch
    (its loss of contact, with the probe inverted by the caller) holds the machine; at rest the rest of the move is aborted and the Outcome is "probed"
    (PROBE_X/Y/Z: the touch; POS_X/Y/Z: where the machine stopped)."""
    start = driver.clock()
    # a stale partial record or a latched error of an earlier run: flush and clear
    check_idle(driver)
    arm = p.CONTROL_PROBE_ARM | p.CONTROL_PROBE_STOP if probe else 0
    driver.write_register("CONTROL", p.CONTROL_ABORT | p.CONTROL_CLEAR | p.CONTROL_ENABLE | p.CONTROL_FILL | arm)
    base = last_executed = driver.read_register("EXECUTED")

    def executed_now() -> int:              # EXECUTED read now, counted from the run's start
        return (driver.read_register("EXECUTED") - base) & 0xFFFFFFFF
    if override is not None and (override.set or probe):     # over the run's settings
        driver.write_register("OVERRIDE", 100 if probe else override.percent)
    if spindle is not None and spindle.set:
        driver.write_register("SPINDLE_OVERRIDE", spindle_scale(spindle.percent))
    fill_bytes = max(1, min(len(stream), driver.free - driver.lmax))
    driver.start_stream(stream)
    snap = Snapshot(records=records, total_bytes=len(stream),
                    override=100 if override is None or probe else override.percent,
                    spindle=100 if spindle is None else spindle.percent)
    held = aborted = paused = False
    stop_note = ""                          # Outcome.message of an abort
    stopping = None                         # link time of a Ctrl-X: holding, then the abort
    hold_write = -1                         # ... the id of its hold write
    after_hold = False                      # this poll round started after that write was acknowledged
    release_write = -1                      # the id of the last write releasing a hold ('~', a pause's end)
    after_release = True                    # this poll round started after it was acknowledged
    filling = True
    touched = False                         # probe: the touch held the machine

    def control(bits: int) -> int:          # hold / resume / abort keep the fill bit while filling
        stop = p.CONTROL_PROBE_STOP if probe and not touched else 0
        return driver.queue_write("CONTROL", bits | p.CONTROL_ENABLE | (p.CONTROL_FILL if filling else 0) | stop)
    paused_since = None
    next_round, polling = driver.clock(), False
    while True:
        if not polling and driver.clock() >= next_round:
            driver.fresh.difference_update(REG[n] for n in POLLED)
            driver.poll(POLLED)                 # a new round of polls, at most every poll_seconds
            after_hold = stopping is not None and driver.writes_done > hold_write
            after_release = driver.writes_done > release_write
            next_round, polling = driver.clock() + driver.poll_seconds, True
        fresh_round = polling and all(REG[n] in driver.fresh for n in POLLED)
        driver.pump()
        if filling and (driver.stream_pos >= fill_bytes or aborted):
            filling = False                     # sequenced after the bytes cut so far
            control(p.CONTROL_HOLD if held else 0)
        if keys is not None:
            for key in keys():
                if key == "!" and not held:
                    control(p.CONTROL_HOLD)
                    held = True
                elif key == "~" and (held or paused) and stopping is None and not touched:
                    release_write, after_release = control(0), False     # (this round's reads may be older)
                    held = paused = False
                    paused_since = None
                elif key == "\x18" and not aborted and filling:
                    driver.drop_stream()
                    control(p.CONTROL_ABORT)       # nothing has moved yet
                    aborted = True
                elif key == "\x18" and not aborted and stopping is None:
                    driver.drop_stream()
                    hold_write = control(p.CONTROL_HOLD)
                    stopping = driver.clock()
                elif spindle is not None and spindle.takes(key):
                    if spindle.press(key):
                        snap.spindle = spindle.percent
                        driver.queue_write("SPINDLE_OVERRIDE", spindle_scale(spindle.percent))
                elif key in OVERRIDE_STEPS or key in OVERRIDE_SETS:
                    # (in a probe move the percent is kept for the next run, which writes it)
                    if override is not None and override.press(key) and not probe:
                        snap.override = override.percent
                        driver.queue_write("OVERRIDE", override.percent)
                elif key == "\x18" and not aborted:
                    control(p.CONTROL_ABORT)       # a second Ctrl-X: at once
                    aborted = True
                    # (at speed the controller latches ERROR 19, which names it below)
        if not fresh_round:
            continue
        polling = False
        v = {n: driver.values[REG[n]] for n in POLLED}
        driver.fresh.difference_update(REG[n] for n in POLLED)
        if (v["EXECUTED"] - last_executed) & 0xFFFFFFFF > 0x7FFFFFFF:   # it only grows: a reset
            raise LinkError(f"{RESET_TEXT} (EXECUTED went back from {last_executed} to {v['EXECUTED']})")
        last_executed = v["EXECUTED"]
        snap.executed = (v["EXECUTED"] - base) & 0xFFFFFFFF
        snap.state, snap.queue_records = field(v["STATUS"], 0, 3), field(v["STATUS"], 8, 8)
        snap.position = [signed32(v[name]) for name in POSITION]
        snap.error, snap.acked_bytes = field(v["ERROR"], 0, 8), driver.acked_bytes
        if progress is not None:
            progress(snap)
        seconds = driver.clock() - start
        if snap.error or snap.state == p.ALARM:
            # motion has stopped: EXECUTED no longer moves (the round's value may be older)
            snap.executed = executed_now()
            if aborted and snap.error == p.ERROR_ABORT_AT_SPEED:     # our abort cut the steps at speed
                return Outcome("aborted", snap.executed, seconds, message=stop_note or f"while moving: {AT_SPEED}")
            return Outcome("error", snap.executed, seconds, snap.error, field(v["ERROR"], 8, 3))
        busy = field(v["STATUS"], 3, 1)
        if probe and v["STATUS"] & p.STATUS_PROBE_VALID and not touched and stopping is None and not aborted:
            touched = True                      # the probe's hold: not a pause of the program
        if touched and not aborted and (snap.state == p.HELD or not busy):
            control(p.CONTROL_ABORT)           # at rest at the touch: the rest of the move goes
            aborted = True
        if touched and aborted and not busy:
            return Outcome("probed", snap.executed, seconds)
        ours = not held or (snap.state == p.HELD and at_pause is not None and at_pause(snap))
        if snap.state in (p.HOLDING, p.HELD) and ours and not aborted and not paused and stopping is None \
                and not touched and after_release:  # (a round from before a release still shows its hold)
            paused, held = True, False          # the program's own pause: the controller held
            # EXECUTED now, at rest (the round's value may be older): which pause it is
            snap.executed = executed_now()
            if on_pause is not None:
                on_pause(snap)
        if paused and snap.state == p.HELD and pause_resume is not None and stopping is None:
            paused_since = driver.clock() if paused_since is None else paused_since
            if driver.clock() - paused_since >= pause_resume:
                release_write, after_release = control(0), False
                paused, paused_since = False, None
        late = stopping is not None and driver.clock() - stopping >= STOP_SECONDS
        if stopping is not None and not aborted and (late or after_hold and (snap.state == p.HELD or not busy)):
            control(p.CONTROL_ABORT)               # at rest on the path (a round read after the hold)
            aborted = True
            stop_note = "" if snap.state in (p.HELD, p.IDLE) else f"not at rest after {STOP_SECONDS:g} s: {AT_SPEED}"
        if aborted and driver.stream_done() and not busy:
            return Outcome("aborted", snap.executed, seconds, message=stop_note)
        if driver.stream_done() and snap.executed >= records and not busy and snap.queue_records == 0 \
                and not paused:                 # (a pause at the end holds until it is released)
            return Outcome("done", snap.executed, seconds)
        if driver.stream_done() and snap.state == p.IDLE and not busy and snap.queue_records == 0 \
                and snap.executed < records and not aborted:
            # every record acknowledged, none waiting, the controller idle: all must have run (the
            # round read EXECUTED before STATUS, so read it again); fewer: they were lost
            snap.executed = executed_now()
            if snap.executed < records:
                raise LinkError(f"{RESET_TEXT} (idle and empty, with records still to run)")
        if max_seconds is not None and seconds > max_seconds:
            return Outcome("timeout", snap.executed, seconds)
