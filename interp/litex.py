# SPDX-License-Identifier: Apache-2.0
"""The controller as a LiteX peripheral: rtl/controller.v behind a LiteX Wishbone slave.

In a LiteX SoC (LiteX 2024.12; docs/controller.md, "Attaching it to a LiteX SoC"):

    from interp.litex import CNCController, io_subsignals
    _io += [("cnc", 0, *io_subsignals({"step": "A1 A2 A3", ...}))]   # or write them yourself
    self.cnc = CNCController(platform, pads=platform.request("cnc"), clk_freq=sys_clk_freq)
    self.bus.add_slave("cnc", self.cnc.bus, SoCRegion(origin=0x9000_0000, size=0x100, cached=False))

LiteX's bus is word-addressed (adr = byte address >> 2): the controller's byte address is
adr[5:0] << 2, so its registers sit at base + their docs/registers.md offset.  The CPU's
firmware drives it through registers only (sw/interp_controller.h): the machine settings,
then the records through CMD_DATA.  The record stream port is tied off and the link
counters read 0.

`pads`: a record (platform.request) with any of the fields of PADS; an output left out is
not driven anywhere, an input left out reads 0 (inactive at INPUT_INVERT 0).  The signals
are also attributes of the module (self.step, self.estop, ...) for logic of your own.
"""
from __future__ import annotations

from migen import Cat, ClockSignal, Constant, Instance, ResetSignal, Signal
from litex.gen import LiteXModule
from litex.soc.interconnect import wishbone

from .flows.synth import RTL, sources

# the controller's machine ports: (name, width, direction), rtl/controller.v
PADS = (("step", 3, "out"), ("dir", 3, "out"), ("enable", 1, "out"),
        ("estop", 1, "in"), ("limit", 3, "in"), ("probe", 1, "in"),
        ("spindle_on", 1, "out"), ("spindle_ccw", 1, "out"), ("spindle_pwm", 1, "out"),
        ("mist", 1, "out"), ("flood", 1, "out"), ("dout", 4, "out"))
# the build's widths (rtl/controller.v's parameters; default: the G-code compiler's build)
WIDTHS = ("W", "FEED_W", "FRAC", "NW", "PF", "LEN_W", "ZW", "MW", "TW", "POS_W", "QDEPTH", "QLW", "SDEPTH")


def family_of(platform) -> str | None:
    """"ecp5" or "ice40" from a LiteX platform's device name (which picks the family's
    forms of the leaf cells, rtl/<family>/), else None (the portable file list)."""
    device = str(getattr(platform, "device", "")).lower()
    if device.startswith("lfe5"):
        return "ecp5"
    if device.startswith("ice40"):
        return "ice40"
    return None


def io_subsignals(pins: dict[str, str], iostandard: str | None = None) -> list:
    """LiteX _io subsignals for the pads: {"step": "A1 A2 A3", "estop": "B1", ...} (one site
    per bit, x first) -> [Subsignal("step", Pins("A1 A2 A3")), ...] (+ IOStandard)."""
    from litex.build.generic_platform import IOStandard, Pins, Subsignal

    known = {name: width for name, width, _ in PADS}
    out = []
    for name, sites in pins.items():
        if name not in known:
            raise ValueError(f"unknown controller pad {name!r}; the pads are {', '.join(known)}")
        if len(sites.split()) != known[name]:
            raise ValueError(f"pad {name}: {known[name]} site(s), got {sites!r}")
        out.append(Subsignal(name, Pins(sites)))
    if iostandard:
        out.append(IOStandard(iostandard))
    return out


class CNCController(LiteXModule):
    """rtl/controller.v with a 32-bit word-addressed LiteX Wishbone slave (`bus`).

    clk_freq: the system clock in Hz (the CLOCK_HZ register and the reset timings).
    curves: 1 = the curve core (about 2100 ECP5 LUT4s; G-code never emits curves).
    queue_aw: the segment queue holds 2^queue_aw bytes.  input_invert, output_invert: INPUT_INVERT
    and OUTPUT_INVERT after reset (active-low pins inactive from the reset on).  widths:
    controller parameters (WIDTHS), for builds other than the G-code compiler's."""

    def __init__(self, platform=None, pads=None, clk_freq: int = 50_000_000, curves: int = 0,
                 queue_aw: int = 12, input_invert: int = 0, output_invert: int = 0, **widths):
        unknown = set(widths) - set(WIDTHS)
        if unknown:
            raise ValueError(f"unknown controller parameter(s): {', '.join(sorted(unknown))}")
        self.bus = bus = wishbone.Interface(data_width=32, adr_width=30, addressing="word")
        for name, width, _ in PADS:
            setattr(self, name, Signal(width, name=name))
        parameters = {"p_CLK_HZ": int(clk_freq), "p_CURVES": int(curves), "p_QUEUE_AW": int(queue_aw),
                      "p_INPUT_INVERT_RESET": int(input_invert), "p_OUTPUT_INVERT_RESET": int(output_invert),
                      **{f"p_{k}": int(v) for k, v in widths.items()}}
        ports = {f"{'o' if direction == 'out' else 'i'}_{name}": getattr(self, name)
                 for name, _, direction in PADS}
        zero16 = Constant(0, 16)
        self.specials += Instance(
            "controller", **parameters,
            i_clk=ClockSignal(), i_rst=ResetSignal(),
            i_cmd_valid=0, i_cmd_data=Constant(0, 8),
            i_wb_adr=Cat(Constant(0, 2), bus.adr[:6]), i_wb_dat_w=bus.dat_w, o_wb_dat_r=bus.dat_r,
            i_wb_we=bus.we, i_wb_sel=bus.sel, i_wb_stb=bus.stb, i_wb_cyc=bus.cyc, o_wb_ack=bus.ack,
            i_link_frames=zero16, i_link_duplicates=zero16, i_link_errors=zero16, i_link_gaps=zero16,
            **ports)
        self.comb += bus.err.eq(0)
        if pads is not None:
            for name, _, direction in PADS:
                if hasattr(pads, name):
                    mine, theirs = getattr(self, name), getattr(pads, name)
                    self.comb += theirs.eq(mine) if direction == "out" else mine.eq(theirs)
        if platform is not None:
            for path in sources("controller", family_of(platform)):
                platform.add_source(str(path))
            platform.add_verilog_include_path(str(RTL))
