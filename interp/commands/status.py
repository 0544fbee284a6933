# SPDX-License-Identifier: Apache-2.0
"""`interp status --port DEVICE` (or --sim): every register of the board controller with
its decoded fields (docs/host-driver.md, docs/registers.md), then the machine position in
mm (POS_X/Y/Z at the machine file's steps/mm: where `interp send` starts a program) and,
with a parameter file, the work position its offsets give."""
from __future__ import annotations

import sys

from ..cores import UsageError
from ..gcode.machine import load_machine
from ..link import registers
from ..gcode.parameter_file import describe
from ..link.driver import Driver, LinkError, read_position, same_pin_setting
from . import gcode as gcode_command          # (its interpret_program looked up at each call)
from . import send
from .send import add_link_options, check_link_args, mm_text


def work_position(machine, position) -> str | None:
    """"work position X.. Y.. Z.. mm (offsets: file)" of a machine position in steps, with the
    parameter file's offsets; None without a parameter file."""
    if machine.parameter_file is None:
        return None
    try:
        program = gcode_command.interpret_program("", machine, position)
    except UsageError as err:
        return f"work position unknown: {err}"
    work = " ".join(f"{axis}{value:.3f}" for axis, value in zip("XYZ", program.end_work))
    return f"work position {work} mm ({describe(program.saved) or 'no offset'}: {machine.parameter_file})"


def cmd_status(args) -> int:
    args.steps = args.line_noise = None
    check_link_args(args)
    machine = load_machine(args.machine, [], None)
    opened = send.open_or_report(args, machine)
    if opened is None:
        return 1
    transport, baud = opened
    try:
        driver = Driver(transport, baud=baud)
        driver.connect()
        values = {name: driver.read_register(address) for name, address in registers.REGISTERS.items()
                  if registers.ACCESS.get(name) != "wo"}
        lines = [registers.describe(name, value) for name, value in values.items()]
        # the machine file's pin settings, which send, home and jog write when they connect
        for name, value in ({} if args.sim else machine.pin_settings()).items():
            if not same_pin_setting(name, values[name], value):
                shown = f"{value}" if name == "SPINDLE_PERIOD" else f"{value:#x}"
                lines.append(f"{name} differs from the machine file's ({shown}, {machine.source}): "
                             "interp send, home and jog write it when they connect")
        # where a program sent now starts (interp send), at the machine file's steps/mm
        position = read_position(driver)
        lines.append(f"machine position {mm_text(machine, position)} mm")
        work = work_position(machine, position)     # and in the work coordinates the file keeps
        if work:
            lines.append(work)
    except LinkError as err:
        print(f"interp: error: link: {err}", file=sys.stderr)
        return 1
    finally:
        transport.close()
    print("\n".join(lines))
    return 0


def add_parser(sub) -> None:
    p_ = sub.add_parser("status", help="read the board controller's registers (UART link)")
    add_link_options(p_, "the Verilator model of the controller instead of a port")
    p_.set_defaults(func=cmd_status)
