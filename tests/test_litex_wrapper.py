# SPDX-License-Identifier: Apache-2.0
"""interp.litex outside simulation (tb/litex/test_litex.py runs the wrapper): the docs' recipe on a LiteX
platform (the pads requested and wired, the family's file list added), the pad helper's
checks, the family by device name."""
import pytest
from migen import Module
from migen.fhdl.verilog import convert
from litex.build.generic_platform import GenericPlatform

from interp.flows.synth import RTL
from interp.litex import PADS, CNCController, family_of, io_subsignals

PINS = {"step": "A1 A2 A3", "dir": "B1 B2 B3", "enable": "C1", "estop": "D1", "limit": "E1 E2 E3",
        "probe": "F1", "spindle_pwm": "G1"}


@pytest.mark.parametrize("device, family", [("LFE5U-25F-6BG381C", "ecp5"), ("ice40-hx8k-ct256", "ice40"),
                                            ("xc7a35ticsg324-1L", None)])
def test_recipe_on_a_platform(device, family):
    platform = GenericPlatform(device, [("cnc", 0, *io_subsignals(PINS, iostandard="LVCMOS33"))])
    pads = platform.request("cnc")
    top = Module()
    top.submodules.cnc = cnc = CNCController(platform, pads=pads, clk_freq=25_000_000)
    assert family_of(platform) == family
    added = {path for path, *_ in platform.sources}
    assert str(RTL / "controller.v") in {str(p) for p in added}
    forms = {p for p in added if "/rtl/ecp5/" in str(p) or "/rtl/ice40/" in str(p)}
    assert all(f"/rtl/{family}/" in str(p) for p in forms) and bool(forms) == (family is not None)
    assert str(RTL) in {str(p) for p in platform.verilog_include_paths}
    bus = cnc.bus
    text = str(convert(top, ios={*pads.flatten(), bus.adr, bus.dat_w, bus.dat_r, bus.sel, bus.cyc, bus.stb,
                                 bus.ack, bus.we}, name="soc"))
    assert ".CLK_HZ(25'd25000000)" in text and ".CURVES(1'd0)" in text
    directions = {name: direction for name, _, direction in PADS}
    for name in PINS:                          # every requested pad reaches the instance
        wire = f"assign cnc_{name} = {name};" if directions[name] == "out" else f"assign {name} = cnc_{name};"
        assert wire in text and f".{name}({name})" in text, name
    assert "spindle_on" in text                # an output left out: the instance's port only


def test_pad_helper_refuses_bad_pads():
    with pytest.raises(ValueError, match="unknown controller pad 'stepx'"):
        io_subsignals({"stepx": "A1"})
    with pytest.raises(ValueError, match="pad limit: 3 site"):
        io_subsignals({"limit": "A1 A2"})
    with pytest.raises(ValueError, match="unknown controller parameter"):
        CNCController(None, clk_freq=1, WIDTH=3)
    assert {name for name, _, _ in PADS} >= set(PINS)


def test_wrapper_follows_the_rtl():
    """PADS and WIDTHS are rtl/controller.v's machine ports and parameters."""
    import re

    from interp.flows.synth import declared_parameters
    from interp.litex import WIDTHS

    text = (RTL / "controller.v").read_text()
    assert declared_parameters(RTL / "controller.v") == set(WIDTHS) | {"CLK_HZ", "CURVES", "QUEUE_AW",
                                                                       "INPUT_INVERT_RESET", "OUTPUT_INVERT_RESET"}
    ports = {name: (direction, int(msb) + 1 if msb else 1) for direction, msb, name in
             re.findall(r"^\s*(input|output)\s+wire\s+(?:\[(\d+):0\]\s+)?(\w+)", text, re.M)}
    for name, width, direction in PADS:
        assert ports[name] == ({"out": "output", "in": "input"}[direction], width), name
