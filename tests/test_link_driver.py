# SPDX-License-Identifier: Apache-2.0
"""The sender (interp.link.driver) against the Python model of the controller's link
(interp.link.devicemodel): delivery under line noise, credits, the build check, machine
errors, hold / resume / abort, a dead link.  Random noise: the seed is printed, SEED=
repeats a run."""
from __future__ import annotations

import os
import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interp.link import driver as driver_module
from interp.link import protocol as p
from interp.link.devicemodel import DeviceModel
from interp.link.driver import (Driver, FeedOverride, LinkError, MismatchError, SpindleOverride, check_controller,
                               configure, run_program, spindle_scale)
from interp.gcode.compile import FEED_W, LEN_W, PF, ZW
from interp.link.records import Build, RecordReader, encode, encode_program, record_bytes

SEED = int(os.environ.get("SEED", random.randrange(1 << 30)))


def commands(n: int) -> list[dict]:
    rng = random.Random(n)
    return [{"kind": 0, "feed": rng.randrange(1, 1 << FEED_W), "x": rng.randrange(-1000, 1000), "y": k, "z": -k,
             "limit": rng.randrange(1 << FEED_W), "rate": rng.randrange(1, 1 << PF), "length": rng.randrange(1 << LEN_W),
             "budget": rng.randrange(1 << ZW)} for k in range(n)]


def run(model: DeviceModel, cmds, **kw):
    driver = Driver(model, baud=model.baud)
    driver.connect()
    check_controller(driver, clock_hz=model.clock_hz)
    configure(driver, {"pulse_width": 30, "setup": 40, "hold": 50},
              {"speed_quantum": (7 << 32) | 5, "block_shift": 3, "jerk_shift": 2, "override": 120})
    stream = b"".join(encode(c) for c in cmds)
    outcome = run_program(driver, stream, len(cmds), **kw)
    return driver, outcome


def executed_fields(model, cmds):
    return [{k: rec[k] for k in cmds[0]} for rec in model.executed]


@pytest.mark.parametrize("noise, count", [(0.0, 60), (0.001, 20), (0.01, 3)])
def test_every_record_once_in_order(noise, count):
    seed = SEED + int(noise * 1e6)
    print(f"seed {seed} (SEED={SEED})")
    cmds = commands(count)
    model = DeviceModel(line_noise=noise, seed=seed, records_per_second=400)
    driver, outcome = run(model, cmds)
    assert outcome.status == "done" and outcome.executed == count
    assert executed_fields(model, cmds) == cmds
    # the settings arrived (each write executed exactly once, in order)
    assert [w for w in model.writes if w[0] != "CONTROL"] == [
        ("PULSE_WIDTH", 30), ("DIR_SETUP", 40), ("DIR_HOLD", 50), ("QUANTUM_LO", 5), ("QUANTUM_HI", 7),
        ("MOTION", 3 | 2 << 4), ("LIMIT_SCALE", 0), ("RATE_SCALE", 0), ("OVERRIDE", 120), ("SPINDLE_OVERRIDE", 256)]
    if noise:
        assert model.errors > 0 and driver.recoveries > 0           # the noise did hit, and was recovered


def test_throughput_without_noise():
    """The record stream at 115200 baud runs at >= 85 % of the line's 11520 bytes/s."""
    cmds = commands(150)
    model = DeviceModel(records_per_second=5000)
    driver, outcome = run(model, cmds)
    rate = record_bytes() * len(cmds) / outcome.seconds
    print(f"{rate:.0f} bytes/s of records over {outcome.seconds:.3f} s link time")
    assert outcome.status == "done" and rate >= 0.85 * 11520
    assert driver.recoveries == 0 and model.gaps == 0 and model.errors == 0


def test_credits_with_a_small_queue():
    """A 512-byte queue and a slow executor: the driver never overruns the credit (no NAK 3)."""
    cmds = commands(25)
    model = DeviceModel(queue_aw=9, records_per_second=40)
    driver, outcome = run(model, cmds)
    assert outcome.status == "done" and executed_fields(model, cmds) == cmds
    assert model.gaps == 0 and driver.naks == 0
    assert outcome.seconds >= 25 / 40


@pytest.mark.parametrize("build, clock, word", [
    (Build(W=16), 50_000_000, r"W 16 \(the program needs 32\)"),
    (Build(PF=20), 50_000_000, "PF 20"),
    (Build(), 25_000_000, "clock is 25000000 Hz"),
])
def test_mismatch_refused(build, clock, word):
    model = DeviceModel(build=build, clock_hz=clock)
    driver = Driver(model)
    driver.connect()
    with pytest.raises(MismatchError, match=word):
        check_controller(driver, clock_hz=50e6)


def test_curves_refused_when_left_out():
    driver = Driver(DeviceModel(curves=False))
    driver.connect()
    with pytest.raises(MismatchError, match="CURVES"):
        check_controller(driver, clock_hz=50e6, curves=True)


def test_speed_settings_wait_for_idle(monkeypatch):
    """QUANTUM and MOTION are taken only while the controller is not busy (as the RTL's
    register block), and CONTROL.fill rises only then: written while busy they keep their
    values and set STATUS.refused until CONTROL.clear; `configure` refuses a busy
    controller in one line, and configures one in ALARM (which flushes: not busy)."""
    settings = {"speed_quantum": (7 << 32) | 5, "block_shift": 3, "jerk_shift": 2}
    timing = {"pulse_width": 30, "setup": 40, "hold": 50}
    model = DeviceModel()
    driver = Driver(model)
    driver.connect()
    model.busy, model.running_until = True, 1e9                  # a record running
    driver.write_register("QUANTUM_LO", 9)
    driver.write_register("OVERRIDE", 50)                       # not a speed setting: taken
    assert driver.read_register("QUANTUM_LO") == 1 and driver.read_register("OVERRIDE") == 50
    assert driver.read_register("STATUS") & p.STATUS_REFUSED
    with pytest.raises(LinkError, match="the controller is busy"):
        configure(driver, timing, settings)
    with monkeypatch.context() as m:                            # busy after the check: read back
        m.setattr(driver_module, "check_idle", lambda driver: None)
        with pytest.raises(LinkError, match="did not take QUANTUM_LO"):
            configure(driver, timing, settings)
    driver.write_register("CONTROL", p.CONTROL_CLEAR)
    assert not driver.read_register("STATUS") & p.STATUS_REFUSED
    driver.write_register("CONTROL", p.CONTROL_FILL | p.CONTROL_ENABLE)   # fill under a program
    assert driver.read_register("CONTROL") == p.CONTROL_ENABLE
    assert driver.read_register("STATUS") & p.STATUS_REFUSED
    driver.write_register("CONTROL", p.CONTROL_CLEAR)
    driver.write_register("CONTROL", p.CONTROL_FILL | p.CONTROL_CLEAR)    # a refusal wins over its clear
    assert driver.read_register("STATUS") & p.STATUS_REFUSED
    model.busy = False
    assert driver.read_register("STATUS") & p.STATUS_REFUSED              # sticky
    driver.write_register("CONTROL", p.CONTROL_CLEAR)
    assert not driver.read_register("STATUS") & p.STATUS_REFUSED
    model.error = 17
    assert driver.read_register("STATUS") & 7 == p.ALARM
    configure(driver, timing, settings)
    assert driver.read_register("QUANTUM_HI") == 7 and driver.read_register("MOTION") == 3 | 2 << 4


def test_machine_error_names_the_record():
    cmds = commands(12)
    model = DeviceModel(fail_at=5, fail_code=17)
    _, outcome = run(model, cmds)
    assert (outcome.status, outcome.error, outcome.limits, outcome.executed) == ("error", 17, 1, 5)
    assert not model.queue and model.reader.bases == [bytes(record_bytes())] * 2   # ALARM flushes, as the controller


def test_compact_records_through_the_model():
    """interp send's compact stream: every record executed once, with its fields."""
    cmds = commands(40)
    model = DeviceModel()
    driver = Driver(model, baud=model.baud)
    driver.connect()
    stream = encode_program(cmds)
    assert len(stream) < record_bytes() * len(cmds)
    outcome = run_program(driver, stream, len(cmds))
    assert outcome.status == "done" and executed_fields(model, cmds) == cmds


def test_bad_record_latches_error_18():
    cmds = commands(3)
    model = DeviceModel()
    driver = Driver(model)
    driver.connect()
    stream = encode(cmds[0]) + bytes([7]) + bytes(83) + encode(cmds[2])
    outcome = run_program(driver, stream, 3)
    assert (outcome.status, outcome.error, outcome.executed) == ("error", 18, 2)


def test_hold_resume_abort_keys():
    """The run starts with the queue filled (CONTROL.fill, then a write clearing it); the keys
    while it runs: hold, resume, abort; a key while it fills keeps the fill bit set."""
    cmds = commands(40)
    model = DeviceModel(records_per_second=100)
    script = iter([""] * 200 + ["!", "", "", "", "~"] + [""] * 30 + ["\x18"])      # a key a pump, ~2 ms
    _, outcome = run(model, cmds, keys=lambda: next(script, ""))
    controls = [v for name, v in model.writes if name == "CONTROL"]
    enable, fill = p.CONTROL_ENABLE, p.CONTROL_FILL
    # Ctrl-X: a feed hold, and the abort once the machine is held (at rest on its path)
    assert controls == [p.CONTROL_ABORT | p.CONTROL_CLEAR | enable | fill, enable, p.CONTROL_HOLD | enable,
                        enable, p.CONTROL_HOLD | enable, p.CONTROL_ABORT | enable]
    assert outcome.status == "aborted" and 0 < outcome.executed < 40 and outcome.message == ""
    assert executed_fields(model, cmds) == cmds[:len(model.executed)]
    # a hold key while the queue fills: the fill stays on until the release, which keeps the hold
    model = DeviceModel(records_per_second=100)
    script = iter(["!"])
    driver = Driver(model)
    driver.connect()
    outcome = run_program(driver, b"".join(encode(c) for c in cmds), len(cmds), keys=lambda: next(script, ""),
                          max_seconds=0.5)
    controls = [v for name, v in model.writes if name == "CONTROL"]
    assert controls[:3] == [p.CONTROL_ABORT | p.CONTROL_CLEAR | enable | fill, p.CONTROL_HOLD | enable | fill,
                            p.CONTROL_HOLD | enable]
    assert outcome.status == "timeout" and len(model.executed) == 0     # held from the start


def test_feed_override_keys():
    """'+' (or '=') '-' by 10 %, '>' '<' by 1 %, '1' .. '9' 10 .. 90 % and '0' 100 % write
    OVERRIDE while the program runs, within Grbl's 10 .. 200 %, from the settings' percent; a
    key that changes nothing writes nothing.  The percent is kept for the next run of the same
    program (its pieces around a probe move) and written at its start over the settings'; a
    probe move runs at 100 % (as Grbl's probing does) and its keys count for the run after
    it; without an override holder the keys do nothing."""
    cmds = commands(40)
    model = DeviceModel(records_per_second=100)
    held = FeedOverride(120)                                # the settings' percent (run's configure)
    script = iter([""] * 100 + ["+", "=", ">"] + [""] * 20 + ["-" * 30, "<", "", "0", "0", "<<", "5"])
    _, outcome = run(model, cmds, keys=lambda: next(script, ""), override=held)
    overrides = [v for name, v in model.writes if name == "OVERRIDE"]
    assert outcome.status == "done" and executed_fields(model, cmds) == cmds
    assert overrides == [120, 130, 140, 141] + list(range(131, 9, -10)) + [10, 100, 99, 98, 50], overrides
    assert held.percent == 50 and model.regs["OVERRIDE"] == 50
    model = DeviceModel(records_per_second=100)
    _, outcome = run(model, cmds, override=held)
    assert [v for name, v in model.writes if name == "OVERRIDE"] == [120, 50]      # settings, then the keys'
    model = DeviceModel(records_per_second=100)
    script = iter(["+"])
    _, outcome = run(model, cmds, keys=lambda: next(script, ""), override=held, probe=True)
    assert [v for name, v in model.writes if name == "OVERRIDE"] == [120, 100] and held.percent == 60
    model = DeviceModel(records_per_second=100)
    script = iter(["+", ">", "0"])
    run(model, cmds, keys=lambda: next(script, ""))
    assert [v for name, v in model.writes if name == "OVERRIDE"] == [120]
    model = DeviceModel(records_per_second=100)
    run(model, cmds, override=FeedOverride(120))                # no key: the settings stand
    assert [v for name, v in model.writes if name == "OVERRIDE"] == [120]
    assert [FeedOverride(p_).after(k) for p_, k in ((195, "+"), (200, ">"), (15, "-"), (10, "<"), (37, "0"),
                                                    (150, "3"), (20, "x"))] == [200, 200, 10, 10, 100, 30, 20]


def test_spindle_override_keys():
    """']' '[' by 10 %, '}' '{' by 1 %, '\\' 100 % write SPINDLE_OVERRIDE (256 = 100 %) while the
    program runs, within 10 .. 200 %; the run's settings write 100 % first; the percent is kept
    for the next run of the same program and written at its start; the feed override keys
    leave it alone, and its keys leave OVERRIDE alone."""
    cmds = commands(40)
    model = DeviceModel(records_per_second=100)
    spindle = SpindleOverride()
    script = iter([""] * 100 + ["]", "]", "}"] + [""] * 20 + ["[", "+"] + ["[" * 30, "{", "\\", "\\", "}"])
    _, outcome = run(model, cmds, keys=lambda: next(script, ""), override=FeedOverride(), spindle=spindle)
    scales = [v for name, v in model.writes if name == "SPINDLE_OVERRIDE"]
    assert outcome.status == "done" and executed_fields(model, cmds) == cmds
    assert scales == [spindle_scale(p_) for p_ in [100, 110, 120, 121, 111, *range(101, 9, -10), 10, 100, 101]], scales
    assert [v for name, v in model.writes if name == "OVERRIDE"] == [120, 110]     # the settings', '+'
    assert spindle.percent == 101 and model.regs["SPINDLE_OVERRIDE"] == 259
    model = DeviceModel(records_per_second=100)
    run(model, cmds, spindle=spindle)
    assert [v for name, v in model.writes if name == "SPINDLE_OVERRIDE"] == [256, 259]    # settings, then the keys'
    assert [spindle_scale(p_) for p_ in (10, 100, 150, 200)] == [26, 256, 384, 512]
    assert [SpindleOverride(p_).after(k) for p_, k in ((195, "]"), (15, "["), (10, "{"), (37, "\\"),
                                                       (50, "+"))] == [200, 10, 10, 100, 50]


def test_resume_key_mid_round_is_no_pause():
    """'!' then '~' typed at every point of a poll round: a round whose reads went out before
    the release still shows HELD, and must not be taken for a program pause (which would wait
    for another '~' and end the run as a timeout)."""
    for offset in range(40):
        model = DeviceModel(records_per_second=100)
        script = iter([""] * 200 + ["!"] + [""] * (200 + offset) + ["~"])
        pauses = []
        _, outcome = run(model, commands(40), keys=lambda: next(script, ""), pause_resume=None, max_seconds=3.0,
                         on_pause=lambda snap: pauses.append(snap.executed))
        assert (outcome.status, pauses, len(model.executed)) == ("done", [], 40), offset


def test_stop_key_aborts_at_rest():
    """Ctrl-X holds first and aborts only once the controller reports HELD: the machine has come
    to rest on its path, so the position counters are the motors' position."""
    cmds = commands(40)
    model = DeviceModel(records_per_second=5, hold_seconds=0.15)         # a 150 ms deceleration
    script = iter([""] * 300 + ["\x18"])
    _, outcome = run(model, cmds, keys=lambda: next(script, ""))
    found = [(v, state) for (name, v), state in zip(model.writes, model.write_states) if name == "CONTROL"]
    enable = p.CONTROL_ENABLE
    assert found[-2:] == [(p.CONTROL_HOLD | enable, p.RUN), (p.CONTROL_ABORT | enable, p.HELD)]
    assert outcome.status == "aborted" and outcome.message == "" and 0 < outcome.executed < 40


def test_stop_key_twice_aborts_at_once():
    """A second Ctrl-X while the feed hold decelerates aborts at once, and says the motors may
    have lost steps; a '~' while stopping does not release the hold."""
    cmds = commands(40)
    model = DeviceModel(records_per_second=100, hold_seconds=1.0)         # a long deceleration
    script = iter([""] * 200 + ["!", "", "\x18", "", "~", "", "\x18"])
    _, outcome = run(model, cmds, keys=lambda: next(script, ""))
    controls = [v for name, v in model.writes if name == "CONTROL"]
    enable = p.CONTROL_ENABLE
    assert controls[-3:] == [p.CONTROL_HOLD | enable, p.CONTROL_HOLD | enable, p.CONTROL_ABORT | enable]
    assert outcome.status == "aborted" and "may have lost steps" in outcome.message


def test_stop_key_twice_at_rest_says_nothing_of_lost_steps():
    """Held already ('!', then HELD): a double Ctrl-X aborts at once but the machine was at rest."""
    model = DeviceModel(records_per_second=5)
    script = iter([""] * 200 + ["!"] + [""] * 300 + ["\x18\x18"])
    _, outcome = run(model, commands(40), keys=lambda: next(script, ""))
    assert outcome.status == "aborted" and outcome.message == ""


class Silent:
    """A port with nothing on it: reads time out in link time."""

    timeout = 0.01

    def __init__(self):
        self.t = 0.0

    def now(self):
        return self.t

    def write(self, data):
        return len(data)

    def read(self, size=1):
        self.t += self.timeout
        return b""


def test_dead_link():
    driver = Driver(Silent())
    with pytest.raises(LinkError, match="no valid frame from the controller for 2 s"):
        driver.connect()
    assert driver.clock() == pytest.approx(2.0, abs=0.1)


def test_link_dies_mid_stream():
    model = DeviceModel()
    driver = Driver(model)
    driver.connect()
    model.noise, model._flip_in = 1.0, 0                          # every bit flips from now on
    driver.start_stream(b"".join(encode(c) for c in commands(10)))
    with pytest.raises(LinkError, match="no valid frame"):
        for _ in range(100000):
            driver.pump()


def test_register_access_under_noise():
    """Reads and writes through a line flipping 1 % of the bits: right values, writes once."""
    print(f"seed {SEED}")
    model = DeviceModel(line_noise=0.01, seed=SEED)
    driver = Driver(model)
    driver.connect()
    for value in (1, 150, 7):
        driver.write_register("OVERRIDE", value)
        assert driver.read_register("OVERRIDE") == value
        assert driver.read_register("ID") == p.ID_VALUE
    assert [v for name, v in model.writes if name == "OVERRIDE"] == [1, 150, 7]


def delivery_case(noise: float, seed: int, count: int, queue_aw: int, rate: float) -> None:
    cmds = commands(count)
    model = DeviceModel(line_noise=noise, seed=seed, queue_aw=queue_aw, records_per_second=rate)
    _, outcome = run(model, cmds)
    assert outcome.status == "done" and executed_fields(model, cmds) == cmds


@settings(max_examples=8, deadline=None, derandomize=True)
@given(noise=st.sampled_from([0.0, 0.0003, 0.002]), seed=st.integers(0, 1 << 20), count=st.integers(1, 12),
       queue_aw=st.integers(7, 12), rate=st.sampled_from([30.0, 300.0, 3000.0]))
def test_delivery_property(noise, seed, count, queue_aw, rate):
    """Any noise, queue size and executor speed: every record once, in order."""
    delivery_case(noise, seed, count, queue_aw, rate)


@pytest.mark.slow
@pytest.mark.parametrize("noise", [0.001, 0.003, 0.01])
def test_delivery_sweep(noise):
    """make test-all: 40 seeds per noise level, 30 records each (4 at 0.01)."""
    for k in range(40):
        seed = SEED + k
        print(f"noise {noise} seed {seed}")
        delivery_case(noise, seed, 4 if noise >= 0.01 else 30, 9, 500.0)


def test_nak_4_repeated_is_one_line_error():
    """A frame the controller keeps refusing as malformed (NAK 4, CRC good) stops the driver
    with one LinkError instead of retransmitting for ever; NAK 3 goes back without shrinking."""
    model = DeviceModel(clock_hz=50_000_000, baud=115200)
    driver = Driver(model, baud=model.baud)
    driver.connect()
    driver.start_stream(bytes(200))
    driver._send_some()
    assert driver.sent
    size = driver.payload
    assert driver._handle(p.Nak(seq=driver.base, reason=p.NAK_CREDIT, free=0)) == "credit"
    driver.recover(shrink=False)
    assert driver.payload == size
    with pytest.raises(LinkError, match="refused a frame"):
        for _ in range(20):
            driver._send_some()
            driver._handle(p.Nak(seq=driver.base, reason=p.NAK_TYPE, free=4096))


class ReleaseWatch(DeviceModel):
    """The model, noting the bytes received (queued + executed) at each CONTROL write."""

    def __init__(self, **kw):
        super().__init__(**kw)
        self.received_at_control = []

    def write_register(self, address, value):
        if address == p.REGISTER_ADDRESSES["CONTROL"]:
            self.received_at_control.append((value, len(self.queue) + self.record_len * len(self.executed)))   # plain records
        super().write_register(address, value)


@pytest.mark.parametrize("index", range(12))
def test_fill_release_follows_the_data_after_a_go_back(index):
    """A program the queue holds whole: the WRITE that clears CONTROL.fill is sequenced after all
    of it, and stays after it when line errors make the driver go back and cut the data again
    (a go-back used to resend the unacknowledged WRITEs first: the run started before its last
    records were in, and their steps came late)."""
    seed = SEED + index                               # (the ids stay the same on every xdist worker)
    print(f"seed {seed} (SEED={SEED})")
    cmds = commands(20)                               # 20 plain records, 1 680 bytes: the fill takes all
    model = ReleaseWatch(line_noise=0.01, seed=seed, records_per_second=400)
    driver, outcome = run(model, cmds)
    assert outcome.status == "done" and executed_fields(model, cmds) == cmds
    release = [received for value, received in model.received_at_control if not value & p.CONTROL_FILL]
    assert release and release[0] == model.record_len * len(cmds), (release, driver.recoveries)


def test_model_refuses_a_frame_that_escapes_the_crc():
    """The model's ideal CRC check: on a noisy line, a frame with a good CRC-16 that the host
    never sent (here: the host's DATA frame with a payload byte changed and the CRC redone,
    as the noise did once in 65,536 corrupted frames) is counted and refused with NAK 1."""
    model = DeviceModel(line_noise=1e-12, seed=1)
    sent = p.encode_frame(p.DATA, 0, bytes(8))
    model.write(sent)                                       # the host's frame (the noise flips nothing)
    model.down.clear()                                      # ... and on the line, a changed one
    for byte in p.encode_frame(p.DATA, 0, bytes([1]) + bytes(7)):
        model.down.append((model.t, byte))
    model.timeout = 0.01
    replies = [p.decode_reply(f) for f in p.FrameParser().feed(model.read(256))]
    assert model.crc_escapes == 1 and not model.queue
    assert [(type(r), r.seq, r.reason) for r in replies] == [(p.Nak, 0, p.NAK_CRC)]
    model.write(sent)                                       # the frame the host did send is taken
    replies = [p.decode_reply(f) for f in p.FrameParser().feed(model.read(256))]
    assert model.queue == bytes(8) and isinstance(replies[-1], p.Ack) and replies[-1].seq == 1


class ResetMidStream(DeviceModel):
    """The controller reset (power glitch, reset button) after its 30th sequenced frame:
    its next expected sequence number is 0 again, its queue empty."""

    def _frame(self, f):
        if self.frames == 30 and self.expected:
            self.expected = 0
            self.queue.clear()
            self.reader = RecordReader(self.build)
        super()._frame(f)


def test_controller_reset_mid_stream_is_one_line_error():
    """The driver stops with one LinkError naming the reset, within the dead-link time (it
    used to go back for ever: the controller's ACKs, for sequence numbers outside the
    window, were ignored yet kept the link alive)."""
    model = ResetMidStream(records_per_second=200)
    driver = Driver(model, baud=model.baud)
    driver.connect()
    with pytest.raises(LinkError, match="was it reset"):
        run_program(driver, b"".join(encode(c) for c in commands(60)), 60, max_seconds=20)
    assert model.t < 5


@pytest.mark.parametrize("reset_at, earlier, hold, why", [
    (0.2, 0, False, "was it reset"),                  # while the records stream: a NAK names it
    (0.45, 0, False, "with records still to run"),     # all sent, some running: idle with records missing
    (0.7, 5, False, "EXECUTED went back"),            # ... after an earlier program: the count went back
    (0.7, 0, True, "was it reset"),                   # held ('!') from the start, waiting for credit:
                                                      # the credit probe's ACK names it
])
def test_a_controller_reset_during_a_run_is_a_link_error(reset_at, earlier, hold, why):
    """The controller reset during a run (power, its board's button): one LinkError, not a run that
    waits forever for records that are gone, nor one that reports them done.  (A program pause
    holds after its record was dispatched, so EXECUTED goes back there too.)"""
    model = DeviceModel(records_per_second=100.0)
    if earlier:
        assert run(model, commands(earlier))[1].status == "done"
    model.reset_at = model.t + reset_at
    keys = iter(["!"])
    count = 4096 // record_bytes() + 12 if hold else 60   # held: more records than the 4 KiB queue holds
    with pytest.raises(LinkError, match=why):
        run(model, commands(count), max_seconds=30.0, keys=(lambda: next(keys, "")) if hold else None)
    assert model.reset_at is None and model.t < 5.0 + earlier        # (it happened, and soon after)


def test_a_hold_in_the_moment_of_a_pause_is_the_pause():
    """'!' typed just as the controller paused by itself (M0), before a poll round saw it: the
    held machine stands where the pause runs (at_pause), so it is told as the program's pause
    and one '~' releases both.  Without at_pause the pause passes untold."""
    from interp.commands.gcode import compile_text
    from interp.commands.send import compile_build, pause_positions, pause_record

    _, compiled = compile_text("G21 G91\nG1 X1 F600\nM0\nG1 X1\nM2\n")
    stream = encode_program(compiled.commands, compile_build(), codes=compiled)
    where = pause_positions(compiled, (0, 0, 0))
    assert list(where.values()) == [(100, 0, 0)]
    told = {}
    for name, at_pause in (("without", None),
                           ("with", lambda snap: where.get(pause_record(compiled, snap.executed)) == tuple(snap.position))):
        model, typed, pauses = DeviceModel(records_per_second=100), [], []

        def keys():
            if model.hold and not typed:
                typed.append("!")
                return "!"
            if typed == ["!"] and (pauses or model.now() > 1.0):
                typed.append("~")
                return "~"
            return ""
        driver = Driver(model, baud=model.baud)
        driver.connect()
        outcome = run_program(driver, stream, len(compiled.commands), keys=keys, pause_resume=None, max_seconds=3.0,
                              on_pause=lambda snap: pauses.append(snap.executed), at_pause=at_pause)
        assert outcome.status == "done" and typed == ["!", "~"], name
        told[name] = pauses
    assert told == {"without": [], "with": [2]}
