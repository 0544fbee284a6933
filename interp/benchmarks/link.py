# SPDX-License-Identifier: Apache-2.0
"""The UART link's record rate, and whether it keeps the controller's queue from starving.

    python -m interp.benchmarks.link [--quick] [--records N] [--only TEXT]

1. Bytes per second: the host driver (interp send's sender) streams N records that
   execute at once (coolant on / off events, as plain records: in their compact form, 7
   bytes, they would come faster than the controller runs events, about 1300 clocks
   each at 50 MHz, and the controller would set the pace) through the simulated link
   (interp.link.simlink: the Verilator model of rtl/uart_controller.v, driven bit by
   bit) at 3 Mbaud and at 115200 baud; the rate is the record bytes over the simulated
   seconds from the first byte sent to the last record acknowledged.  The ceiling the
   frame format allows (DATA frames of LMAX payload bytes, 6 bytes of overhead, 10 bits
   a byte) is given beside it, and the records per second that rate carries at
   RECORD_BYTES a record (plain records: 68 at the default build).
2. Queue level: for each corpus program (the densest first: the most records per second
   of machine time), its compact records (the bytes interp send sends) at the measured
   byte rate give its records per second; the planned end time of every command
   (interp.gcode.compile's command_time: the planner's trapezoid times and the dwells)
   is played against records arriving at that rate whenever the controller has room for
   them.  The controller holds CAPACITY records (its segment queue, 2^QUEUE_AW bytes, at
   the program's mean record size, plus motion_top's command queue), full at the start
   (the driver fills it, or the program is shorter).  The lowest level is the fewest
   records waiting ahead of the running one at any command's start (before the
   program's last CAPACITY records, where the queue drains by design); 0 with waits > 0:
   the queue starves (the machine waits for the link).
"""
from __future__ import annotations

import argparse
import sys
from bisect import bisect_right

from ..gcode.machine import load_machine
from .gcode_corpus import corpus_files

BAUDS = (3_000_000, 115_200)
QUEUE_BYTES = 4096          # the segment queue at QUEUE_AW = 12
QDEPTH = 8                  # motion_top's command queue at the CLI build
LMAX = 128
FRAME_OVERHEAD = 6


def ceiling(baud: int, record_bytes: int) -> float:
    """Records per second the frame format allows at `baud` (full DATA frames, no gaps)."""
    return baud / 10.0 * LMAX / (LMAX + FRAME_OVERHEAD) / record_bytes


def capacity(record_bytes: int) -> int:
    return QUEUE_BYTES // record_bytes + QDEPTH


def queue_low(command_time: list[float], rate: float, slots: int) -> tuple[int, int]:
    """(lowest level, commands that waited) of a program whose command k ends at
    command_time[k] machine seconds when nothing waits; record k arrives 1 / rate after
    record k - 1 and not before a slot is free (command k - slots ended), the first
    `slots` there at time 0; a command whose record is not there waits for it (and
    everything after it moves later).  Level at the start of command k: the records
    there (arrived, not started) after it was taken; the lowest over the commands
    that still have `slots` or more records after them."""
    n = len(command_time)
    if n == 0:
        return 0, 0
    arrival, starts, ends = [0.0] * n, [0.0] * n, [0.0] * n
    waits = 0
    for k in range(n):
        if k >= slots:
            arrival[k] = max(arrival[k - 1] + 1.0 / rate, ends[k - slots])
        start = ends[k - 1] if k else 0.0
        if arrival[k] > start:
            waits += 1
            start = arrival[k]
        starts[k] = start
        ends[k] = start + command_time[k] - (command_time[k - 1] if k else 0.0)
    # while `slots` or more records are still to come (at the end the queue drains by design)
    lowest = min((bisect_right(arrival, starts[k]) - k - 1 for k in range(max(1, n - slots))), default=slots)
    return lowest, waits


def measure_rate(baud: int, records: int, machine=None, seed: int = 1, line_noise: float = 0.0) -> dict:
    """Stream `records` instant records (alternate M8 / M9 coolant events, plain records: the
    controller takes them far faster than the link brings them, so the link sets the pace)
    with the host driver through the simulated link: {"records", "seconds" (simulated, first record
    frame to the last one acknowledged), "rate" (records/s), "executed", and SimLink's
    figures (cycles, cycles_per_second, ...)}."""
    from ..commands.gcode import compile_text
    from ..commands.send import compile_build, encode_program
    from ..link import protocol as p
    from ..link.driver import Driver, check_controller, configure
    from ..link.simlink import SimLink

    machine = machine or load_machine()
    text = "\n".join("M8" if k % 2 == 0 else "M9" for k in range(records)) + "\n"
    _, compiled = compile_text(text, machine)
    stream = encode_program(compiled.commands, compile_build(), compact_records=False)
    link = SimLink(baud=baud, machine=machine, seed=seed, line_noise=line_noise)
    try:
        driver = Driver(link, baud=baud)
        driver.connect()
        check_controller(driver, compile_build(), machine.clock_hz)
        configure(driver, machine.timing(), compiled.settings, compiled)
        driver.write_register("CONTROL", p.CONTROL_ABORT | p.CONTROL_CLEAR | p.CONTROL_ENABLE)
        base = driver.read_register("EXECUTED")
        start = link.now()
        driver.start_stream(stream)
        while not driver.stream_done():
            driver.pump()
        seconds = link.now() - start
        executed = (driver.read_register("EXECUTED") - base) & 0xFFFFFFFF
    finally:
        result = link.close()
    return {**result, "records": len(compiled.commands), "bytes": len(stream), "seconds": seconds,
            "rate": len(compiled.commands) / seconds, "byte_rate": len(stream) / seconds, "executed": executed}


def dense_programs(only: str | None = None, count: int | None = None, machine=None):
    """[(name, commands, machine seconds, command_time, stream bytes)] of the corpus programs
    that compile, the most commands per machine second first (stream: interp send's
    compact records)."""
    from ..commands.gcode import compile_text
    from ..commands.send import compile_build, encode_program

    machine = machine or load_machine()
    out = []
    for path in corpus_files():
        if only and only not in path.name:
            continue
        try:
            _, compiled = compile_text(path.read_text(errors="replace"), machine)
        except Exception:                  # noqa: BLE001 - a program the front end refuses
            continue
        if compiled.commands and compiled.machine_time_s > 0:
            out.append((path.name, len(compiled.commands), compiled.machine_time_s, list(compiled.command_time),
                        len(encode_program(compiled.commands, compile_build(),
                                                           codes=compiled))))
    out.sort(key=lambda row: -row[1] / row[2])
    return out[:count] if count else out


def tables(quick: bool, records: int | None = None, only: str | None = None):
    from ..link.records import record_bytes

    size = record_bytes()
    records = records or (200 if quick else 1000)
    rates = []
    for baud in BAUDS:
        m = measure_rate(baud, records if baud > 200_000 else max(20, records // 5))
        rates.append((baud, m))
    per_baud = ceiling(1, 1)                # the frame format's payload bytes/s per baud
    rate_rows = [[baud, m["records"], m["bytes"], round(m["seconds"], 4), round(m["byte_rate"]),
                  round(baud * per_baud), round(m["byte_rate"] / (baud * per_baud), 3),
                  round(m["byte_rate"] / size, 1),
                  f"{m['cycles_per_second']:.3g}"] for baud, m in rates]
    rows = []
    for name, n, seconds, times, stream in dense_programs(only, 3 if quick else 8):
        mean = stream / n
        row = [name, n, round(seconds, 2), round(n / seconds, 1), round(mean, 1)]
        for baud, m in rates:
            rate = m["byte_rate"] / mean
            low, waits = queue_low(times, rate, capacity(round(mean)))
            row += [round(rate), f"{low} of {capacity(round(mean))}", waits]
        rows.append(row)
    head = ["program", "records", "machine time (s)", "records/s needed", "bytes/record"]
    for baud, _ in rates:
        head += [f"records/s @{baud}", f"lowest level @{baud}", f"waits @{baud}"]
    return [("Link: record bytes per second through the simulated UART link (host driver, simulated seconds)",
             ["baud", "records", "bytes", "seconds", "bytes/s", "ceiling bytes/s", "of ceiling",
              f"records/s at {size} bytes", "sim cycles/s"], rate_rows),
            ("Link: records per second and lowest queue level (records ahead of the running one) on the "
             "densest corpus programs, compact records", head, rows)]


def main(argv: list[str] | None = None) -> int:
    from ..commands.bench import markdown

    parser = argparse.ArgumentParser(prog="python -m interp.benchmarks.link", description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer records and programs")
    parser.add_argument("--records", type=int, help="records streamed for the rate (default 1000, quick 200)")
    parser.add_argument("--only", help="only corpus programs whose name contains this text")
    args = parser.parse_args(argv)
    if args.records is not None and args.records < 1:
        parser.error("--records must be >= 1")
    for title, header, rows in tables(args.quick, args.records, args.only):
        print(markdown(title, header, rows), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

