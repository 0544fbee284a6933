# SPDX-License-Identifier: Apache-2.0
"""segment_queue: every cycle against a cycle model (a list for the block RAM, the read
register and its `held` flag): order, no byte lost or duplicated, level / free / in_ready
at every fill up to full (2^AW bytes), free whole records, flush at random cycles (seeded)."""
import cocotb
from cocotb.triggers import FallingEdge

from interp.simulation.runner import run_cocotb
from interp.testing.controllerkit import icarus_in_make_test
from interp.testing.tbkit import TB, seeded_rng


class Model:
    def __init__(self, aw):
        self.size = 1 << aw
        self.ram, self.held, self.data = [], False, None

    def level(self):
        return len(self.ram) + self.held

    def clock(self, in_valid, in_data, out_ready, flush):
        if flush:
            self.ram, self.held = [], False
            return
        write = in_valid and self.level() != self.size
        take = self.held and out_ready
        fetch = bool(self.ram) and (not self.held or out_ready)
        if fetch:
            self.data = self.ram.pop(0)
        if write:
            self.ram.append(in_data)
        self.held = fetch or (self.held and not take)


@cocotb.test()
async def random_traffic(dut):
    """Bursts of writes and reads at random rates (the queue runs full and empty), flushes."""
    rng = seeded_rng(dut, "random_traffic")
    aw, record_bytes = int(dut.AW.value), int(dut.RECORD_BYTES.value)
    tb = TB(dut)
    idle = {"in_valid": 0, "in_data": 0, "out_ready": 0, "flush": 0}
    await tb.reset(idle)
    model, written, read, full_seen = Model(aw), [], [], 0
    for phase in range(12):
        p_in, p_out = rng.choice([(0.9, 0.2), (0.2, 0.9), (0.6, 0.6), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)])
        for _ in range(rng.randint(20, 120)):
            level = int(dut.level.value)
            assert level == model.level(), f"level {level}, model {model.level()}"
            assert int(dut.free.value) == model.size - level
            assert int(dut.free_records.value) == (model.size - level) // record_bytes
            assert int(dut.in_ready.value) == (level != model.size)
            assert int(dut.out_valid.value) == model.held
            if model.held:
                assert int(dut.out_data.value) == model.data
            full_seen += level == model.size
            inputs = {"in_valid": int(rng.random() < p_in), "in_data": rng.randrange(256),
                      "out_ready": int(rng.random() < p_out), "flush": int(rng.random() < 0.003)}
            if inputs["flush"]:
                written, read = [], []
            else:
                if inputs["in_valid"] and level != model.size:
                    written.append(inputs["in_data"])
                if inputs["out_ready"] and model.held:
                    read.append(model.data)
            model.clock(inputs["in_valid"], inputs["in_data"], inputs["out_ready"], inputs["flush"])
            await tb.tick(inputs)
        assert read == written[:len(read)], f"phase {phase}: bytes out of order or lost"
    assert full_seen, "the queue never ran full"
    # drain: every byte written comes out once
    tb.drive({**idle, "out_ready": 1})
    for _ in range(model.size + 4):
        if model.held:
            read.append(model.data)
        model.clock(0, 0, 1, 0)
        await FallingEdge(dut.clk)
    assert read == written and int(dut.level.value) == 0


def test_segment_queue(sim):
    icarus_in_make_test(sim)
    run_cocotb(toplevel="segment_queue", test_module="test_segment_queue", sim=sim, parameters={"AW": 4, "RECORD_BYTES": 5},
               name="segment_queue")
