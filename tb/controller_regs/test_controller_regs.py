# SPDX-License-Identifier: Apache-2.0
"""controller_regs on its own, cycle by cycle: wb_ack exactly one cycle after a strobe is seen
(one cycle high, back-to-back accesses), read data with the ack; a CMD_DATA write held
until data_ready, then data_write for one cycle with the word; CONTROL's abort / clear /
probe_arm one-cycle strobes (abort and clear in the ack cycle), hold and enable RW, hold_set
(winning over a CONTROL write in its clock); the status inputs composed into
STATUS, ERROR, QUEUE_FREE, OUTPUTS and the sign-extended positions at POS_W 20; the speed
settings refused while busy (STATUS.refused until CONTROL.clear), taken at rest; CONTROL.fill
rising while busy only with abort."""
import cocotb
from cocotb.triggers import FallingEdge, ReadOnly

from interp.simulation.runner import run_cocotb
from interp.testing.controllerkit import REG, icarus_in_make_test
from interp.testing.tbkit import TB

STATUS_IN = {"state": 0, "busy": 0, "stopped": 0, "probe_valid": 0, "records": 0, "error_code": 0,
             "error_limits": 0, "free_bytes": 0, "free_records": 0, "pos_x": 0, "pos_y": 0, "pos_z": 0,
             "probe_x": 0, "probe_y": 0, "probe_z": 0, "inputs": 0, "outputs": 0, "duty": 0, "link_frames": 0,
             "link_duplicates": 0, "link_errors": 0, "link_gaps": 0, "executed": 0, "hold_set": 0, "data_ready": 0}
STROBES = ("data_write", "abort_strobe", "clear_strobe", "arm_strobe")
BUS = {"wb_adr": 0, "wb_dat_w": 0, "wb_we": 0, "wb_sel": 0, "wb_stb": 0, "wb_cyc": 0}


async def access(tb, address, value=None, ready_after=0):
    """One classic cycle; returns (cycles to ack, read data, strobes seen per cycle)."""
    dut = tb.dut
    tb.drive({"wb_adr": address, "wb_dat_w": value or 0, "wb_we": int(value is not None), "wb_stb": 1,
              "wb_cyc": 1, "wb_sel": 0, "data_ready": int(ready_after == 0)})
    seen = []
    for cycle in range(1, 50):
        await ReadOnly()
        seen.append({n: int(getattr(dut, n).value) for n in STROBES})
        await FallingEdge(dut.clk)
        if cycle >= ready_after:
            tb.drive({"data_ready": 1})
        if int(dut.wb_ack.value):
            data = int(dut.wb_dat_r.value)
            # the ack cycle's strobes (CONTROL's are registered; data_write is not, and is low)
            seen.append({n: int(getattr(dut, n).value) for n in STROBES})
            tb.drive({**BUS, "data_ready": 0})
            await FallingEdge(dut.clk)
            assert not int(dut.wb_ack.value), "ack longer than a cycle"
            return cycle, data, seen
    raise AssertionError(f"no ack for address {address:#x}")


@cocotb.test()
async def bus_and_fields(dut):
    tb = TB(dut)
    await tb.reset({**STATUS_IN, **BUS})
    cycles, data, _ = await access(tb, REG["ID"])
    assert (cycles, data) == (1, 0x494E5450)
    # CMD_DATA waits for data_ready; data_write strobes once, with the word
    cycles, _, seen = await access(tb, REG["CMD_DATA"], 0xA1B2C3D4, ready_after=5)
    assert cycles == 6 and [s["data_write"] for s in seen] == [0] * 5 + [1, 0], seen
    # CONTROL strobes: one cycle each, abort and clear in the ack cycle, probe_arm in the
    # access cycle; hold, enable and fill kept
    _, _, seen = await access(tb, REG["CONTROL"], 0b111111)
    assert [(s["abort_strobe"], s["clear_strobe"], s["arm_strobe"]) for s in seen] == [(0, 0, 1), (1, 1, 0)]
    assert int(dut.hold.value) == 1 and int(dut.enable.value) == 1 and int(dut.fill.value) == 1
    assert (await access(tb, REG["CONTROL"]))[1] == 0b110001
    await access(tb, REG["CONTROL"], 0)
    tb.drive({"hold_set": 1})
    await FallingEdge(dut.clk)
    tb.drive({"hold_set": 0})
    assert (await access(tb, REG["CONTROL"]))[1] == 0b00001, "hold_set sets CONTROL.hold"
    # a CONTROL write that clears hold in the very clock of a hold_set (a probe's touch, an
    # M0) keeps the hold: the touch is never lost to a host write
    await access(tb, REG["CONTROL"], 0)
    tb.drive({**BUS, "wb_adr": REG["CONTROL"], "wb_dat_w": 0b10000, "wb_we": 1, "wb_stb": 1, "wb_cyc": 1,
              "hold_set": 1})
    await FallingEdge(dut.clk)
    assert int(dut.wb_ack.value), "the write was taken in the clock of the hold_set"
    tb.drive({**BUS, "hold_set": 0})
    await FallingEdge(dut.clk)
    assert (await access(tb, REG["CONTROL"]))[1] == 0b10001, "the write's hold 0 lost the touch"
    await access(tb, REG["CONTROL"], 0)
    # composed status: POS_W 20, sign-extended
    tb.drive({"state": 3, "busy": 1, "stopped": 1, "probe_valid": 1, "records": 200, "error_code": 17,
              "error_limits": 5, "free_bytes": 1234, "free_records": 14, "pos_x": (1 << 20) - 3, "pos_z": 77,
              "outputs": 0xF3, "duty": 0xBEEF, "executed": 0xDEADBEEF})
    assert (await access(tb, REG["STATUS"]))[1] == 3 | 8 | 16 | 32 | 200 << 8
    assert (await access(tb, REG["ERROR"]))[1] == 17 | 5 << 8
    assert (await access(tb, REG["QUEUE_FREE"]))[1] == 1234 | 14 << 16
    assert (await access(tb, REG["POS_X"]))[1] == 0xFFFFFFFD
    assert (await access(tb, REG["POS_Z"]))[1] == 77
    assert (await access(tb, REG["OUTPUTS"]))[1] == 0xBEEF00F3
    assert (await access(tb, REG["EXECUTED"]))[1] == 0xDEADBEEF
    # the speed settings while busy: refused (the registers and outputs keep their values),
    # STATUS.refused (bit 7) until CONTROL.clear; the other settings are taken
    for name in ("QUANTUM_LO", "QUANTUM_HI", "MOTION", "LIMIT_SCALE", "RATE_SCALE"):
        await access(tb, REG[name], 0x5A)
    await access(tb, REG["OVERRIDE"], 42)
    assert (int(dut.quantum.value), int(dut.block_shift.value), int(dut.jerk_shift.value)) == (1, 2, 0)
    assert [int(getattr(dut, n).value) for n in ("limit_scale", "limit_shift", "rate_scale", "rate_shift")] == [0] * 4
    assert (await access(tb, REG["OVERRIDE"]))[1] == 42
    assert (await access(tb, REG["STATUS"]))[1] == 3 | 8 | 16 | 32 | 128 | 200 << 8
    await access(tb, REG["CONTROL"], 0b00100)
    assert (await access(tb, REG["STATUS"]))[1] == 3 | 8 | 16 | 32 | 200 << 8
    # CONTROL.fill rises while busy only with abort; the write's other bits are taken
    await access(tb, REG["CONTROL"], 0b110001)
    assert (await access(tb, REG["CONTROL"]))[1] == 0b010001 and int(dut.fill.value) == 0
    assert (await access(tb, REG["STATUS"]))[1] & 128
    await access(tb, REG["CONTROL"], 0b100110)                  # abort + clear + fill
    assert (await access(tb, REG["CONTROL"]))[1] == 0b100000 and int(dut.fill.value) == 1
    assert not (await access(tb, REG["STATUS"]))[1] & 128
    await access(tb, REG["CONTROL"], 0b110000)                  # kept while busy, then cleared
    assert (await access(tb, REG["CONTROL"]))[1] == 0b110000
    await access(tb, REG["CONTROL"], 0)
    assert (await access(tb, REG["CONTROL"]))[1] == 0 and not (await access(tb, REG["STATUS"]))[1] & 128
    # a refused fill and a clear in one write: the refusal wins (clear is in the ack cycle)
    await access(tb, REG["CONTROL"], 0b100100)
    assert int(dut.fill.value) == 0 and (await access(tb, REG["STATUS"]))[1] & 128
    await access(tb, REG["CONTROL"], 0b000100)
    assert not (await access(tb, REG["STATUS"]))[1] & 128
    # quantum: FEED_W 40 across LO and HI, at rest
    tb.drive({"busy": 0})
    await access(tb, REG["QUANTUM_LO"], 0x12345678)
    await access(tb, REG["QUANTUM_HI"], 0xFFFFFFFF)
    await access(tb, REG["MOTION"], 0xFFEDC05A)                 # the code shifts: bits 13:8, 21:16
    await access(tb, REG["LIMIT_SCALE"], 0x89ABCDEF)
    await access(tb, REG["RATE_SCALE"], 0xFEDCBA98)
    assert int(dut.quantum.value) == 0xFF12345678
    assert (await access(tb, REG["QUANTUM_HI"]))[1] == 0xFF
    assert (int(dut.block_shift.value), int(dut.jerk_shift.value)) == (0xA, 0x5)
    assert [int(getattr(dut, n).value) for n in ("limit_scale", "limit_shift", "rate_scale", "rate_shift")] \
        == [0x89ABCDEF, 0x00, 0xFEDCBA98, 0x2D]
    assert (await access(tb, REG["MOTION"]))[1] == 0x2D005A
    assert not (await access(tb, REG["STATUS"]))[1] & 128


def test_controller_regs(sim):
    icarus_in_make_test(sim)
    run_cocotb(toplevel="controller_regs", test_module="test_controller_regs", sim=sim,
               parameters={"POS_W": 20, "FEED_W": 40}, name="controller_regs")
