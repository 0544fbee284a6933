# SPDX-License-Identifier: Apache-2.0
"""The register map: regs/controller.rdl and the files generated from it (make regs).

The committed outputs are what the generator writes, `--check` catches a stale or
missing one, the C header compiles, addresses are unique and aligned, and the
Python constants equal the Verilog include's.  Plus the contract's addresses
and fixed values, describe(), and one-line errors for a bad .rdl.
"""
from __future__ import annotations

import re
import shutil
import subprocess
import sys

import pytest

from interp import regs
from interp.link import registers

pytest.importorskip("systemrdl", reason="systemrdl-compiler missing (the `test` extra)")
pytest.importorskip("peakrdl_cheader", reason="peakrdl-cheader missing (the `test` extra)")

# COMMON25 section 3 and 7: the contract between the controller and the host.
CONTRACT = {"ID": 0x00, "VERSION": 0x04, "BUILD0": 0x08, "BUILD1": 0x0C, "CLOCK_HZ": 0x10, "QUEUE_SIZE": 0x14,
            "STATUS": 0x18, "ERROR": 0x1C, "QUEUE_FREE": 0x20, "POS_X": 0x24, "POS_Y": 0x28, "POS_Z": 0x2C,
            "PROBE_X": 0x30, "PROBE_Y": 0x34, "PROBE_Z": 0x38, "INPUTS": 0x3C, "CONTROL": 0x40, "OVERRIDE": 0x44,
            "PULSE_WIDTH": 0x48, "DIR_SETUP": 0x4C, "DIR_HOLD": 0x50, "QUANTUM_LO": 0x54, "QUANTUM_HI": 0x58,
            "MOTION": 0x5C, "INPUT_INVERT": 0x60, "SPINDLE_PERIOD": 0x64, "OUTPUTS": 0x68, "LINK_FRAMES": 0x6C,
            "LINK_ERRORS": 0x70, "CMD_DATA": 0x74, "EXECUTED": 0x78, "OUTPUT_INVERT": 0x7C,
            "INPUT_FILTER": 0x80, "SPINDLE_OVERRIDE": 0x84, "LIMIT_SCALE": 0x88, "RATE_SCALE": 0x8C}
WRITABLE = {"CONTROL", "OVERRIDE", "PULSE_WIDTH", "DIR_SETUP", "DIR_HOLD", "QUANTUM_LO", "QUANTUM_HI", "MOTION",
            "INPUT_INVERT", "SPINDLE_PERIOD", "POS_X", "POS_Y", "POS_Z", "OUTPUT_INVERT",
            "INPUT_FILTER", "SPINDLE_OVERRIDE", "LIMIT_SCALE", "RATE_SCALE"}   # (POS_*: set at rest, homing)


@pytest.fixture(scope="module")
def outputs():
    return regs.generate()


def test_outputs_are_up_to_date(outputs, tmp_path):
    """The committed files equal a fresh run of the generator into tmp."""
    assert regs.main(["--root", str(tmp_path)]) == 0
    for rel in regs.OUTPUTS:
        fresh = (tmp_path / rel).read_text()
        assert fresh == outputs[rel], f"{rel}: two runs differ"
        assert (regs.ROOT / rel).read_text() == fresh, f"{rel} is stale: run make regs"
    assert regs.main(["--check"]) == 0


@pytest.mark.parametrize("rel", regs.OUTPUTS)
def test_check_catches_a_stale_file(outputs, tmp_path, capsys, rel):
    for name, text in outputs.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    assert regs.main(["--check", "--root", str(tmp_path)]) == 0
    (tmp_path / rel).write_text(outputs[rel].replace("0x", "0y", 1) + "\n")
    capsys.readouterr()
    assert regs.main(["--check", "--root", str(tmp_path)]) == 1
    assert capsys.readouterr().err.strip() == f"regs: stale: {rel} (run make regs)"
    (tmp_path / rel).unlink()
    assert regs.main(["--check", "--root", str(tmp_path)]) == 1


def test_check_from_the_command_line(tmp_path):
    """`python -m interp.regs --check`: exit 1 and one line per missing output."""
    done = subprocess.run([sys.executable, "-m", "interp.regs", "--check", "--root", str(tmp_path)],
                          capture_output=True, text=True, cwd=regs.ROOT, timeout=120)
    assert done.returncode == 1
    assert done.stderr.splitlines() == [f"regs: stale: {rel} (run make regs)" for rel in regs.OUTPUTS]


def test_c_header_compiles(tmp_path):
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("gcc missing")
    source = tmp_path / "use.c"
    source.write_text('#include "interp_controller.h"\n#include <stddef.h>\n'
                      f'_Static_assert(offsetof(controller_t, EXECUTED) == {CONTRACT["EXECUTED"]}, "EXECUTED");\n'
                      f'_Static_assert(CONTROLLER__STATUS__RECORDS_bp == 8, "records");\n'
                      "int controller_status_offset(void) { return (int)offsetof(controller_t, STATUS); }\n")
    for command in ([gcc, "-Wall", "-Werror", "-c", str(regs.ROOT / "sw" / "interp_controller.h"),
                     "-o", str(tmp_path / "h.gch")],
                    [gcc, "-std=c11", "-Wall", "-Wextra", "-Werror", "-I", str(regs.ROOT / "sw"), "-c", str(source),
                     "-o", str(tmp_path / "use.o")]):
        done = subprocess.run(command, capture_output=True, text=True, timeout=60)
        assert done.returncode == 0, done.stderr


def test_addresses_unique_aligned_and_as_agreed():
    addresses = list(registers.REGISTERS.values())
    assert len(set(addresses)) == len(addresses)
    assert all(a % 4 == 0 and 0 <= a <= 0xFC for a in addresses)
    assert registers.REGISTERS == CONTRACT


def test_fields_fit_and_do_not_overlap():
    used = {}
    for key, (lsb, width, access) in registers.FIELDS.items():
        name = key.split(".")[0]
        assert name in registers.REGISTERS, key
        assert width >= 1 and lsb + width <= 32, key
        assert access in ("ro", "rw", "wo", "w1p"), key
        bits = ((1 << width) - 1) << lsb
        assert not used.get(name, 0) & bits, f"{key} overlaps"
        used[name] = used.get(name, 0) | bits


def test_access_as_agreed():
    assert {n for n, a in registers.ACCESS.items() if a == "rw"} == WRITABLE
    assert {n for n, a in registers.ACCESS.items() if a == "wo"} == {"CMD_DATA"}
    pulses = {k for k, (_, _, a) in registers.FIELDS.items() if a == "w1p"}
    assert pulses == {"CONTROL.abort", "CONTROL.clear", "CONTROL.probe_arm"}
    assert registers.FIELDS["CONTROL.hold"] == (0, 1, "rw")
    assert registers.FIELDS["CONTROL.enable"] == (4, 1, "rw")
    assert registers.FIELDS["CONTROL.probe_stop"] == (6, 1, "rw")
    assert registers.FIELDS["STATUS.position_set"] == (16, 3, "ro")


def test_fixed_values_at_the_default_build():
    r = registers.RESETS
    assert r["ID"] == 0x494E5450 and bytes.fromhex(f"{r['ID']:08X}") == b"INTP"
    assert r["VERSION"] == 1 | 68 << 8 | 32 << 16 | 32 << 24
    assert r["BUILD0"] == 34 | 32 << 8 | 24 << 16 | 16 << 24
    assert r["BUILD1"] == 66 | 68 << 8 | 12 << 16 | 16 << 24
    assert r["CLOCK_HZ"] == 50_000_000
    assert r["QUEUE_SIZE"] == 4096 | 12 << 16 | 1 << 24
    assert r["OVERRIDE"] == 100 and r["QUANTUM_LO"] == 1 and r["QUANTUM_HI"] == 0
    assert r["PULSE_WIDTH"] == r["DIR_SETUP"] == r["DIR_HOLD"] == 25          # 0.5 us at 50 MHz
    assert r["SPINDLE_PERIOD"] == 50_000_000 // 20_000
    assert r["CONTROL"] == r["INPUT_INVERT"] == 0 and r["MOTION"] == 2         # block_shift 2
    assert registers.FIELDS["QUANTUM_HI.value"][1] == 34 - 32               # FEED_W - 32


def _vh_constants() -> dict[str, int]:
    text = (regs.ROOT / "rtl" / "controller_regs.vh").read_text()
    out = {}
    for name, value in re.findall(r"^localparam\s+(?:\[7:0\]|integer)\s+(\w+)\s*=\s*([^;]+);", text, re.M):
        sized = re.fullmatch(r"8'h([0-9A-Fa-f]+)", value.strip())
        out[name] = int(sized.group(1), 16) if sized else int(value)
    return out


def test_python_constants_equal_the_verilog_include():
    vh = _vh_constants()
    python = {f"REG_{n}": a for n, a in registers.REGISTERS.items()}
    for key, (lsb, width, _) in registers.FIELDS.items():
        stem = key.replace(".", "_").upper()
        python[f"{stem}_LSB"] = lsb
        python[f"{stem}_WIDTH"] = width
    assert vh == python
    assert all(getattr(registers, f"REG_{n}") == a for n, a in registers.REGISTERS.items())


def test_verilog_include_lints_clean(tmp_path):
    """The include inside a module: Verilator -Wall and Icarus -g2005 are silent."""
    from interp.simulation.runner import verilator_bin

    top = tmp_path / "regs_include.v"
    top.write_text("`default_nettype none\nmodule regs_include (input wire [7:2] adr, output wire hit);\n"
                   '`include "controller_regs.vh"\n'
                   "    assign hit = adr[7:2] == REG_STATUS[7:2] && STATUS_RECORDS_LSB == 8;\n"
                   "endmodule\n`default_nettype wire\n")
    verilator = verilator_bin()
    verilator = verilator / "verilator" if verilator.is_dir() else verilator
    done = subprocess.run([str(verilator), "--lint-only", "-Wall", f"-I{regs.ROOT / 'rtl'}", str(top)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and "%Warning" not in done.stderr, done.stderr
    if shutil.which("iverilog"):
        done = subprocess.run(["iverilog", "-g2005", f"-I{regs.ROOT / 'rtl'}", "-o", str(tmp_path / "a.out"), str(top)],
                              capture_output=True, text=True, timeout=60)
        assert done.returncode == 0 and not done.stderr, done.stderr


@pytest.mark.parametrize("name, value, expected", [
    ("STATUS", 0x0000_0301, "STATUS 0x00000301: state=RUN busy=0 stopped=0 probe_valid=0 enabled=0 refused=0 records=3 "
                            "position_set=0"),
    ("STATUS", 0x0005_FF7C, "STATUS 0x0005FF7C: state=ALARM busy=1 stopped=1 probe_valid=1 enabled=1 refused=0 "
                            "records=255 position_set=5"),
    ("STATUS", 0x0000_0007, "STATUS 0x00000007: state=7 busy=0 stopped=0 probe_valid=0 enabled=0 refused=0 records=0 "
                            "position_set=0"),
    ("STATUS", 0x0000_0080, "STATUS 0x00000080: state=IDLE busy=0 stopped=0 probe_valid=0 enabled=0 refused=1 records=0 "
                            "position_set=0"),
    ("ERROR", 0x0000_0511, "ERROR 0x00000511: code=LIMIT_SWITCH limits=5"),
    ("ERROR", 0x0000_0010, "ERROR 0x00000010: code=ESTOP limits=0"),
    ("ERROR", 0x0000_0063, "ERROR 0x00000063: code=99 limits=0"),
    ("POS_X", 0xFFFF_FFF4, "POS_X -12"),
    ("PROBE_Z", 0x7FFF_FFFF, "PROBE_Z 2147483647 (0x7FFFFFFF)"),
    ("CLOCK_HZ", 50_000_000, "CLOCK_HZ 50000000 (0x02FAF080)"),
    ("QUEUE_FREE", 0x0030_1000, "QUEUE_FREE 0x00301000: bytes=4096 records=48"),
    ("OUTPUTS", 0x8000_0035, "OUTPUTS 0x80000035: spindle_on=1 spindle_ccw=0 mist=1 flood=0 digital=3 spindle_duty=32768"),
])
def test_describe(name, value, expected):
    assert registers.describe(name, value) == expected


@pytest.mark.parametrize("name, value, message", [
    ("NOPE", 0, "unknown register 'NOPE'"),
    ("STATUS", -1, "STATUS: value -1 is not a 32-bit register value"),
    ("STATUS", 1 << 32, "STATUS: value 4294967296 is not a 32-bit register value"),
])
def test_describe_refuses_bad_input(name, value, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        registers.describe(name, value)


def test_every_register_is_described():
    for name in registers.REGISTERS:
        line = registers.describe(name, 0)
        assert line.startswith(name + " ") and "\n" not in line


@pytest.mark.parametrize("bad, where", [
    ("reg { field { sw = rw; } a[3:0] = 4'd0; } X @ 0x02;\n", "overlaps with 'ID'"),
    ("reg { field { sw = rw; } a[3:0] = 4'd0; } X @ 0x92;\n", "X: address 0x92 is not a multiple of 4"),
    ("reg { field { sw = rw; } a[3:0] = 4'd0; } X @ 0x100;\n", "X: address 0x100 is beyond the register block's read-back table"),
    ("reg { field { sw = rw; } a[3:0] = 4'd0; } STATUS @ 0x90;\n", "Multiple declarations of instance 'STATUS'"),
    ("reg { field { sw = rw; } a[3:0] = 4'd0 } Y @ 0x90;\n", "error: missing ';'"),
])
def test_bad_rdl_is_one_line(tmp_path, bad, where):
    """A broken .rdl: exit status 1, one line naming the file, no traceback."""
    text = regs.RDL.read_text()
    rdl = tmp_path / "broken.rdl"
    rdl.write_text(text.replace("} EXECUTED @ 0x78;\n", "} EXECUTED @ 0x78;\n" + bad))
    done = subprocess.run([sys.executable, "-m", "interp.regs", "--check", "--rdl", str(rdl)],
                          capture_output=True, text=True, cwd=regs.ROOT, timeout=120)
    assert done.returncode == 1
    lines = done.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("regs: ") and where in lines[0], done.stderr
    assert "Traceback" not in done.stderr


def test_missing_rdl_is_one_line(tmp_path, capsys):
    assert regs.main(["--check", "--rdl", str(tmp_path / "none.rdl")]) == 1
    assert capsys.readouterr().err.strip() == f"regs: {tmp_path / 'none.rdl'}: no such file"


# ------------------------------------------------------------ the RTL against the map
# rtl/controller.v (module controller, COMMON ports) read and written through its Wishbone
# port on Icarus: resets at the default build, read-only registers ignore writes, read-write
# fields read back what was written (write-1 pulses read 0), unknown addresses read 0 and
# ignore writes, wb_adr[1:0] ignored, every access acknowledged within 2 clocks.
DEFAULT_BUILD = {"CLK_HZ": 50_000_000, "W": 32, "FEED_W": 34, "FRAC": 32, "NW": 24, "PF": 16, "LEN_W": 66,
                 "ZW": 68, "MW": 12, "TW": 16, "POS_W": 32, "QUEUE_AW": 12, "CURVES": 1}
UNKNOWN = (0x90, 0xC0, 0xFC)

_BENCH = """`timescale 1ns/1ps
`default_nettype none
module regs_map_tb;
    reg clk = 1'b0, rst = 1'b1;
    always #5 clk = ~clk;
    reg  [7:0]  adr = 8'd0;
    reg  [31:0] dat_w = 32'd0;
    reg         we = 1'b0, stb = 1'b0, cyc = 1'b0;
    wire [31:0] dat_r;
    wire        ack, cmd_ready, enable, spindle_on, spindle_ccw, spindle_pwm, mist, flood;
    wire [15:0] queue_free;
    wire [7:0]  status_state, status_error;
    wire [2:0]  step, dir;
    wire [3:0]  dout;
    integer     waited;
    controller #(PARAMS) dut (
        .clk(clk), .rst(rst), .cmd_valid(1'b0), .cmd_data(8'd0), .cmd_ready(cmd_ready),
        .queue_free(queue_free), .wb_adr(adr), .wb_dat_w(dat_w), .wb_dat_r(dat_r), .wb_we(we),
        .wb_sel(4'hF), .wb_stb(stb), .wb_cyc(cyc), .wb_ack(ack),
        .link_frames(16'd0), .link_duplicates(16'd0), .link_errors(16'd0), .link_gaps(16'd0),
        .status_state(status_state), .status_error(status_error), .step(step), .dir(dir),
        .enable(enable), .estop(1'b0), .limit(3'b000), .probe(1'b0), .spindle_on(spindle_on),
        .spindle_ccw(spindle_ccw), .spindle_pwm(spindle_pwm), .mist(mist), .flood(flood), .dout(dout));
    task access(input write, input [7:0] address, input [31:0] value);
        begin
            @(negedge clk);
            adr = address; dat_w = value; we = write; stb = 1'b1; cyc = 1'b1; waited = 1;
            @(posedge clk); #1;
            while (!ack && waited < 9) begin waited = waited + 1; @(posedge clk); #1; end
            $display("%s %02h %08h %0d", write ? "W" : "R", address, write ? value : dat_r, ack ? waited : 99);
            @(negedge clk);
            stb = 1'b0; cyc = 1'b0; we = 1'b0;
        end
    endtask
    initial begin
        repeat (4) @(posedge clk);
        rst = 1'b0;
        repeat (40) @(posedge clk);
ACCESSES
        $finish;
    end
endmodule
"""


def _rw_mask(name: str) -> int:
    return sum(((1 << w) - 1) << lsb for key, (lsb, w, a) in registers.FIELDS.items()
               if key.split(".")[0] == name and a == "rw")


def _map_accesses() -> list[tuple[int, int, int]]:
    """(write, address, value) in order: the reset state first, then writes."""
    ro = [n for n, a in registers.ACCESS.items() if a == "ro"]
    out = [(0, a, 0) for a in registers.REGISTERS.values()] + [(0, a, 0) for a in UNKNOWN] + [(0, 0x03, 0)]
    for name in ro:
        out += [(1, registers.REGISTERS[name], 0xFFFF_FFFF), (0, registers.REGISTERS[name], 0)]
    for address in UNKNOWN:
        out += [(1, address, 0xFFFF_FFFF), (0, address, 0)]
    order = sorted(WRITABLE - {"CONTROL", "INPUT_INVERT"}) + ["CONTROL", "INPUT_INVERT"]
    for name in order:   # INPUT_INVERT last: inverted inputs trip the e-stop
        a = registers.REGISTERS[name]
        for value in (0xFFFF_FFFF, 0x5A5A_A5A5, 0):
            out += [(1, a | 2, value), (0, a, 0)]
    return out


def run_map_bench(rtl, tmp_path) -> tuple[list, list[str]]:
    """Simulate the accesses on rtl/controller.v; the accesses and the bench's lines."""
    from interp.flows.synth import sources

    accesses = _map_accesses()
    params = ", ".join(f".{k}({v})" for k, v in DEFAULT_BUILD.items())
    body = "\n".join(f"        access(1'b{w}, 8'h{a:02X}, 32'h{v:08X});" for w, a, v in accesses)
    bench = tmp_path / "regs_map_tb.v"
    bench.write_text(_BENCH.replace("PARAMS", params).replace("ACCESSES", body))
    files = [str(p) for p in sources("controller", rtl=rtl)]
    binary = tmp_path / "regs_map_tb.vvp"
    done = subprocess.run(["iverilog", "-g2005", "-o", str(binary), f"-I{rtl}", "-s", "regs_map_tb", str(bench), *files],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    done = subprocess.run(["vvp", "-n", str(binary)], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return accesses, [line for line in done.stdout.splitlines() if line[:2] in ("R ", "W ")]


def map_mismatches(accesses, lines) -> list[str]:
    """Where the simulated accesses disagree with the map (empty: conforms)."""
    assert len(lines) == len(accesses), lines[-3:]
    names = {a: n for n, a in registers.REGISTERS.items()}
    bad, seen, last_write = [], {}, {}
    for (write, address, value), line in zip(accesses, lines):
        kind, shown, got, cycles = line.split()
        got, cycles = int(got, 16), int(cycles)
        name = names.get(address & 0xFC, f"0x{address:02X}")
        if cycles > 2:
            bad.append(f"{kind} {name}: acknowledged after {cycles} clocks (at most 2)")
        if write:
            last_write[address & 0xFC] = value
            continue
        if address & 0xFC not in names:
            expected = 0
        elif address & 0xFC in last_write and registers.ACCESS[name] == "rw":
            expected = last_write[address & 0xFC] & _rw_mask(name)
        elif name in seen:
            expected = seen[name]                                   # read-only: writes ignored
        elif registers.RESETS[name] is None:                      # STATUS: stopped follows motion_top
            expected = got & ~0xFF07                               # IDLE, no records
        else:
            expected = registers.RESETS[name] if name != "CMD_DATA" else 0
        if got != expected:
            bad.append(f"R {name}: 0x{got:08X}, want 0x{expected:08X}"
                       + (f" (after writing 0x{last_write[address & 0xFC]:08X})" if address & 0xFC in last_write else ""))
        seen.setdefault(name, got)
    return bad


@pytest.mark.skipif(not (regs.ROOT / "rtl" / "controller.v").is_file(), reason="rtl/controller.v not merged yet")
@pytest.mark.skipif(shutil.which("iverilog") is None, reason="iverilog missing")
def test_controller_implements_the_map(tmp_path):
    accesses, lines = run_map_bench(regs.ROOT / "rtl", tmp_path)
    assert map_mismatches(accesses, lines) == []


def test_map_check_catches_a_wrong_value():
    """The comparison fails on a wrong reset, a writable read-only register and a slow ack."""
    accesses = [(0, 0x44, 0), (1, 0x00, 0xFFFF_FFFF), (0, 0x00, 0), (0, 0x90, 0)]
    lines = ["R 44 00000064 1", "W 00 ffffffff 1", "R 00 494e5450 2", "R 90 00000000 1"]
    assert map_mismatches(accesses, lines) == []
    lines = ["R 44 00000063 1", "W 00 ffffffff 1", "R 00 ffffffff 3", "R 90 00000001 1"]
    assert map_mismatches(accesses, lines) == ["R OVERRIDE: 0x00000063, want 0x00000064",
                                               "R ID: acknowledged after 3 clocks (at most 2)",
                                               "R ID: 0xFFFFFFFF, want 0x494E5450 (after writing 0xFFFFFFFF)",
                                               "R 0x90: 0x00000001, want 0x00000000"]


def test_bad_option_is_one_line(capsys):
    with pytest.raises(SystemExit) as stop:
        regs.main(["--frobnicate"])
    assert stop.value.code == 2
    assert capsys.readouterr().err.strip() == "python -m interp.regs: unrecognized arguments: --frobnicate"


def test_compose_is_field_inverted():
    """compose packs fields where field() finds them, and refuses a field the register does
    not have or a value that does not fit."""
    from interp.link.registers import compose, field

    value = compose("MOTION", block_shift=3, jerk_shift=2, limit_shift=44, rate_shift=49)
    assert value == 0x312C23
    assert [field(f"MOTION.{n}", value) for n in ("block_shift", "jerk_shift", "limit_shift", "rate_shift")] \
        == [3, 2, 44, 49]
    for bad in ({"block_shift": 16}, {"rate_shift": -1}, {"speed": 1}):
        with pytest.raises(ValueError):
            compose("MOTION", **bad)
