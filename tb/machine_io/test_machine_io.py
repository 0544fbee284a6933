# SPDX-License-Identifier: Apache-2.0
"""machine_io: every event code against a model of the outputs (spindle on / ccw / duty,
mist, flood, dout, pause), seeded random event sequences with values out of range; `off`;
the PWM duty measured over whole periods for several (duty, period) pairs, periods below
the multiplier's 17 clocks and 0 included: high for exactly floor(duty * period / 65536)
clocks of each period (duty 65535: always)."""
import cocotb
from cocotb.triggers import FallingEdge

from interp.simulation.runner import run_cocotb
from interp.testing.controllerkit import icarus_in_make_test
from interp.testing.tbkit import TB, seeded_rng

IDLE = {"event_valid": 0, "event_code": 0, "event_value": 0, "off": 0, "period": 100}


class Outputs:
    def __init__(self):
        self.on = self.ccw = self.mist = self.flood = 0
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

    def off(self):
        self.on = self.mist = self.flood = 0

    def read(self, dut):
        return {"on": int(dut.spindle_on.value), "ccw": int(dut.spindle_ccw.value), "duty": int(dut.duty.value),
                "mist": int(dut.mist.value), "flood": int(dut.flood.value), "dout": int(dut.dout.value)}

    def want(self):
        return {"on": self.on, "ccw": self.ccw, "duty": self.duty, "mist": self.mist, "flood": self.flood,
                "dout": self.dout}


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
        pause = int(dut.pause.value)
        if off:
            model.off()
        else:
            model.event(code, value)
        assert pause == int(code == 10), f"event {n}: pause {pause} for code {code}"
        tb.drive(IDLE)
        await FallingEdge(dut.clk)
        assert model.read(dut) == model.want(), f"event {n} ({code}, {value}, off {off}): " \
            f"{model.read(dut)}, want {model.want()}"


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
        tb.drive({**IDLE, "period": period})
        length = max(period, 1)
        for _ in range(3 * length + 40):               # the threshold settles within two periods (or 34 clocks)
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
        want = length if duty == 65535 else duty * length >> 16
        assert high == [want] * 3, f"duty {duty}, period {period}: high {high}, want {want}"
    tb.drive({**IDLE, "event_valid": 1, "event_code": 3})
    await FallingEdge(dut.clk)
    tb.drive(IDLE)
    for _ in range(300):
        await FallingEdge(dut.clk)
        assert not int(dut.spindle_pwm.value), "PWM while the spindle is off"


def test_machine_io(sim):
    icarus_in_make_test(sim)
    for w in (32, 16):
        run_cocotb(toplevel="machine_io", test_module="test_machine_io", sim=sim, parameters={"W": w},
                   name="machine_io")
