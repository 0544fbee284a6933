# SPDX-License-Identifier: Apache-2.0
"""machine_io: every event code against a model of the outputs (spindle on / ccw / duty,
mist, flood, dout, pause, laser mode and the spindle pin it gates while `held`, a register a
clock after the state), seeded
random event sequences with values out of range; `off`;
the PWM duty measured over whole periods for several (duty, period) pairs, periods below
the multiplier's 29 clocks and 0 included: high for exactly floor(duty * period / 65536)
clocks of each period (duty 65535: always); the spindle override: (duty, scale, period)
triples, seeded random ones among them, high for floor(level * period / 65536) with level =
min(duty * scale / 256, 65535) (65535: always), M3 and the laser's M4 power alike."""
import cocotb
from cocotb.triggers import FallingEdge

from interp.simulation.runner import run_cocotb
from interp.testing.controllerkit import icarus_in_make_test
from interp.testing.tbkit import TB, seeded_rng

IDLE = {"event_valid": 0, "event_code": 0, "event_value": 0, "off": 0, "period": 100, "held": 0, "scaled": 0,
        "scale": 256}


class Outputs:
    def __init__(self):
        self.on = self.ccw = self.mist = self.flood = self.laser = 0
        self.duty = self.dout = 0

    def event(self, code, value):
        duty = min(max(value, 0), 65535)
        if code in (1, 2):
            self.on, self.ccw, self.duty = 1, int(code == 2), duty
        elif code == 3:
            self.on = 0
        elif code == 4:
            self.duty = duty
        elif code in (5, 6):
            setattr(self, "mist" if code == 5 else "flood", 1)
        elif code in (7, 12):
            self.mist = self.flood = 0
            if code == 12:
                self.on = 0
        elif code in (8, 9) and 0 <= value <= 3:
            self.dout = self.dout | 1 << value if code == 8 else self.dout & ~(1 << value)
        elif code == 13:
            self.laser = int(value != 0)

    def off(self):
        self.on = self.mist = self.flood = self.laser = 0

    def read(self, dut):
        return {"on": int(dut.spindle_on.value), "ccw": int(dut.spindle_ccw.value), "duty": int(dut.duty.value),
                "mist": int(dut.mist.value), "flood": int(dut.flood.value), "dout": int(dut.dout.value),
                "pin": int(dut.spindle_pin.value)}

    def want(self, held):
        return {"on": self.on, "ccw": self.ccw, "duty": self.duty, "mist": self.mist, "flood": self.flood,
                "dout": self.dout, "pin": int(self.on and not (self.laser and held))}


@cocotb.test()
async def events(dut):
    rng = seeded_rng(dut, "events")
    w = int(dut.W.value)
    tb = TB(dut)
    await tb.reset(IDLE)
    model = Outputs()
    for n in range(400):
        code = rng.choice(list(range(0, 14)) + [rng.randint(14, 255)])
        value = rng.choice([rng.randint(-5, 5), rng.randint(0, 65535), rng.randint(-(1 << (w - 1)), (1 << (w - 1)) - 1),
                            65535, 65536])
        value = max(min(value, (1 << (w - 1)) - 1), -(1 << (w - 1)))
        off = rng.random() < 0.05
        tb.drive({**IDLE, "event_valid": 1, "event_code": code, "event_value": value & ((1 << w) - 1), "off": int(off)})
        await FallingEdge(dut.clk)
        # the pin is a register: at the event's edge it took the spindle state before the event
        assert int(dut.spindle_pin.value) == model.on, f"event {n}: the spindle pin is not a clock behind"
        pause = int(dut.pause.value)
        if off:
            model.off()
        else:
            model.event(code, value)
        assert pause == int(code == 10), f"event {n}: pause {pause} for code {code}"
        held = int(rng.random() < 0.3)
        tb.drive({**IDLE, "held": held})
        await FallingEdge(dut.clk)
        assert model.read(dut) == model.want(held), f"event {n} ({code}, {value}, off {off}, held {held}): " \
            f"{model.read(dut)}, want {model.want(held)}"


async def high_per_period(dut, tb, inputs, length):
    """Clocks the PWM is high in each of 3 whole periods, once the threshold has settled (within
    two periods and 58 clocks)."""
    tb.drive(inputs)
    for _ in range(2 * length + 60):
        await FallingEdge(dut.clk)
    while int(dut.counter.value) != 0:
        await FallingEdge(dut.clk)
    high = []
    for _ in range(3):
        count = 0
        for _ in range(length):
            count += int(dut.spindle_pwm.value)
            await FallingEdge(dut.clk)
        high.append(count)
    return high


@cocotb.test()
async def pwm_duty(dut):
    tb = TB(dut)
    await tb.reset(IDLE)
    for duty, period in [(16384, 100), (32768, 7), (1, 1000), (65535, 50), (0, 50), (40000, 16), (50000, 0),
                         (65534, 1), (30000, 17), (12345, 333)]:
        if duty >> (int(dut.W.value) - 1):
            continue                                    # does not fit a narrow event value
        tb.drive({**IDLE, "event_valid": 1, "event_code": 1, "event_value": duty, "period": period})
        await FallingEdge(dut.clk)
        length = max(period, 1)
        high = await high_per_period(dut, tb, {**IDLE, "period": period}, length)
        want = length if duty == 65535 else duty * length >> 16
        assert high == [want] * 3, f"duty {duty}, period {period}: high {high}, want {want}"
    for mode, held in ((1, 1), (0, 1), (1, 0)):     # laser mode: the beam is off while held
        tb.drive({**IDLE, "event_valid": 1, "event_code": 13, "event_value": mode})
        await FallingEdge(dut.clk)
        tb.drive({**IDLE, "held": held})
        high = 0
        for _ in range(300):
            await FallingEdge(dut.clk)
            high += int(dut.spindle_pwm.value)
        assert (high == 0) == bool(mode and held), f"laser {mode}, held {held}: PWM high {high} of 300"
    tb.drive({**IDLE, "event_valid": 1, "event_code": 3})
    await FallingEdge(dut.clk)
    tb.drive(IDLE)
    for _ in range(300):
        await FallingEdge(dut.clk)
        assert not int(dut.spindle_pwm.value), "PWM while the spindle is off"


@cocotb.test()
async def laser_dynamic_power(dut):
    """Laser mode with M4: the PWM runs at `scaled` (power_scale's duty x speed / feed); with
    M3, or M4 without laser mode, at the duty."""
    tb = TB(dut)
    await tb.reset(IDLE)
    period, duty, scaled = 200, 30000, 16384               # (a duty that fits W = 16)
    for laser, code, want in ((1, 2, scaled), (1, 1, duty), (0, 2, duty)):
        for event in ((13, laser), (code, duty)):
            tb.drive({**IDLE, "event_valid": 1, "event_code": event[0], "event_value": event[1], "period": period})
            await FallingEdge(dut.clk)
        high = await high_per_period(dut, tb, {**IDLE, "period": period, "scaled": scaled}, period)
        assert high == [want * period >> 16] * 3, f"laser {laser}, M{code + 2}: high {high}"


def high_want(level, period):
    """Clocks high of each period at this level (65535: always)."""
    length = max(period, 1)
    return length if level >= 65535 else level * length >> 16


@cocotb.test()
async def spindle_override(dut):
    """SPINDLE_OVERRIDE's scale: the PWM at min(duty x scale / 256, 65535) for M3, and for M4
    in laser mode at `scaled` x scale / 256; scale 256 is the duty itself."""
    rng = seeded_rng(dut, "spindle_override")
    tb = TB(dut)
    await tb.reset(IDLE)
    wide = int(dut.W.value) > 17
    cases = [(30000, 256, 100), (30000, 282, 100), (30000, 26, 333), (40000, 512, 50), (65535, 128, 40),
             (65535, 1023, 7), (0, 1023, 20), (20000, 0, 20), (32768, 512, 64), (1000, 1, 1000)]
    cases += [(rng.randrange(65536), rng.randrange(1024), rng.randrange(1, 300)) for _ in range(6)]
    for duty, scale, period in cases:
        if not wide and duty >> (int(dut.W.value) - 1):
            continue                                    # does not fit a narrow event value
        tb.drive({**IDLE, "event_valid": 1, "event_code": 1, "event_value": duty, "period": period, "scale": scale})
        await FallingEdge(dut.clk)
        high = await high_per_period(dut, tb, {**IDLE, "period": period, "scale": scale}, max(period, 1))
        want = high_want(min(duty * scale >> 8, 65535), period)
        assert high == [want] * 3, f"duty {duty}, scale {scale}, period {period}: high {high}, want {want}"
        assert int(dut.duty.value) == duty, "OUTPUTS.duty keeps the programmed duty"
    period, scaled = 200, 16384                            # laser mode, M4: the power is scaled too
    for event in ((13, 1), (2, 3000)):
        tb.drive({**IDLE, "event_valid": 1, "event_code": event[0], "event_value": event[1], "period": period})
        await FallingEdge(dut.clk)
    for scale in (256, 384, 64):
        high = await high_per_period(dut, tb, {**IDLE, "period": period, "scaled": scaled, "scale": scale}, period)
        assert high == [high_want(scaled * scale >> 8, period)] * 3, f"laser M4, scale {scale}: high {high}"


def test_machine_io(sim):
    icarus_in_make_test(sim)
    for w in (32, 16):
        run_cocotb(toplevel="machine_io", test_module="test_machine_io", sim=sim, parameters={"W": w},
                   name="machine_io")
