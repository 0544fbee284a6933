# SPDX-License-Identifier: Apache-2.0
"""input_guard: the synchronizer's two clocks and the polarity (seeded random pin changes
against a model of the two flops); the step outputs gated in the very cycle the synchronized
e-stop shows active (and while it stays active), in the cycle a limit switch becomes active
(only then), and while `alarm` is high; the probe latch (arm, edge, latched position, no
latch without arming)."""
import cocotb
from cocotb.triggers import FallingEdge, ReadOnly

from interp.simulation.runner import run_cocotb
from interp.testing.controllerkit import icarus_in_make_test
from interp.testing.tbkit import TB, seeded_rng

IDLE = {"estop": 0, "limit": 0, "probe": 0, "invert": 0, "alarm": 0, "probe_arm": 0, "step_in": 0,
        "pos_x": 0, "pos_y": 0, "pos_z": 0, "filter_period": 0, "filter_mask": 0b11111}


@cocotb.test()
async def synchronizer_and_gate(dut):
    rng = seeded_rng(dut, "synchronizer_and_gate")
    tb = TB(dut)
    await tb.reset(IDLE)
    meta, synced, previous = 0, 0, 0
    invert = 0
    gated = 0
    for cycle in range(3000):
        if rng.random() < 0.05:
            invert = rng.randrange(32) if rng.random() < 0.2 else invert
        raw = {"estop": int(rng.random() < 0.1), "limit": rng.randrange(8) if rng.random() < 0.3 else 0,
               "probe": rng.randrange(2)}
        alarm = int(rng.random() < 0.1)
        step_in = rng.randrange(8)
        tb.drive({**IDLE, **raw, "invert": invert, "alarm": alarm, "step_in": step_in})
        await ReadOnly()
        inputs = synced ^ invert
        rising = inputs & ~previous
        gate = alarm or inputs & 1 or rising & 0b1110
        assert int(dut.inputs.value) == inputs, f"cycle {cycle}"
        assert int(dut.estop_trip.value) == inputs & 1
        assert int(dut.limit_trip.value) == rising >> 1 & 7
        assert int(dut.step_out.value) == (0 if gate else step_in), f"cycle {cycle}: gate {gate}"
        gated += bool(gate and step_in)
        await FallingEdge(dut.clk)
        previous = inputs
        synced, meta = meta, raw["estop"] | raw["limit"] << 1 | raw["probe"] << 4
    assert gated > 100


@cocotb.test()
async def probe_latch(dut):
    tb = TB(dut)
    await tb.reset(IDLE)
    pos = {"pos_x": 100, "pos_y": (-7) & 0xFFFFFFFF, "pos_z": 3}

    async def probe_edge(level=1):
        for k in range(6):
            tb.drive({**IDLE, **{a: v + k for a, v in pos.items()}, "probe": level})
            await FallingEdge(dut.clk)

    await probe_edge()                                  # not armed: nothing latched
    assert not int(dut.probe_valid.value) and int(dut.probe_x.value) == 0
    tb.drive({**IDLE, **pos, "probe_arm": 1})
    await FallingEdge(dut.clk)
    tb.drive({**IDLE, **pos})
    await FallingEdge(dut.clk)
    assert not int(dut.probe_valid.value)
    await FallingEdge(dut.clk)
    await probe_edge()
    # the pin rises before edge 1, meta at 1, synced at 2, latched at 3 with the position of cycle 2
    assert int(dut.probe_valid.value)
    assert [int(getattr(dut, f"probe_{a}").value) for a in "xyz"] == [(v + 2) & 0xFFFFFFFF for v in pos.values()]
    tb.drive({**IDLE, "probe": 0})
    for _ in range(4):
        await FallingEdge(dut.clk)
    await probe_edge()                                  # a second edge: kept
    assert int(dut.probe_x.value) == 102
    tb.drive({**IDLE, "probe_arm": 1})
    await FallingEdge(dut.clk)
    assert not int(dut.probe_valid.value), "probe_arm clears probe_valid"


@cocotb.test()
async def filtered_inputs(dut):
    """The filter sits between the synchronizer and the polarity: with INPUT_FILTER's period
    10, a limit glitch of 30 clocks never trips, a change of 40 trips (once); the e-stop,
    left out of the mask, trips in the clock the synchronizer shows it."""
    tb = TB(dut)
    on = {**IDLE, "filter_period": 10, "filter_mask": 0b11110}
    await tb.reset(on)

    async def hold(inputs, clocks):
        trips = estop = 0
        for _ in range(clocks):
            tb.drive({**on, **inputs, "step_in": 7})
            await ReadOnly()
            trips += int(dut.limit_trip.value) != 0
            estop += int(dut.estop_trip.value)
            await FallingEdge(dut.clk)
        return trips, estop

    assert await hold({"limit": 0b010}, 30) == (0, 0)
    assert await hold({}, 60) == (0, 0)
    assert await hold({"limit": 0b010}, 30) == (0, 0), "the trip comes 33 .. 42 clocks after the pin"
    assert await hold({"limit": 0b010}, 30) == (1, 0)
    assert await hold({"estop": 1}, 3) == (0, 1), "unfiltered: active in the synchronizer's clock"


def test_input_guard(sim):
    icarus_in_make_test(sim)
    run_cocotb(toplevel="input_guard", test_module="test_input_guard", sim=sim, name="input_guard")
