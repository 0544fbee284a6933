# SPDX-License-Identifier: Apache-2.0
"""`interp home`: the homing cycle, as Grbl's $H runs it (docs/host-driver.md, "Homing").

  interp home --port DEVICE [--baud B] [--machine FILE.toml] [--axes XYZ]

Each axis with a home end in the machine file (`axis.X.home = "min"` or "max"), in
`homing.order`: a seek towards its limit switch at `homing.seek_mm_min` (the switch
stops the steps in the clock it shows, ERROR 17), a pull-off of `homing.pull_off_mm`,
a slow approach at `homing.locate_mm_min`, then POS_<axis> is set to that travel end
(`axis.X.min_mm` or `max_mm`: the switch is machine coordinate min_mm or max_mm) and
the axis pulls off again.  The moves are compiled as `interp gcode` compiles a G91 G1
move, without the travel limits (the position is not known yet).  Exit status: 0 homed,
1 a switch not found, still active after a pull-off, another error or a link error, 2
usage (no axis to home).
"""
from __future__ import annotations

import sys

from ..cores import UsageError
from ..gcode.machine import AXES, Machine, load_machine
from ..link import protocol as p
from ..link.driver import (Driver, LinkError, MismatchError, check_controller, check_idle, configure,
                           read_position, run_program)
from ..link.records import encode_program
from .gcode import compile_text
from . import send
from .send import add_link_options, check_link_args, compile_build, mm_text

SEEK_TRAVELS = 1.5          # the seek goes at most 1.5 travels (and a pull-off) towards the switch


class HomingError(Exception):
    """The cycle cannot go on: one line."""


def unlimited(machine: Machine) -> Machine:
    """The machine without its travel limits: homing moves start where the position is unknown."""
    values = {section: dict(keys) for section, keys in machine.values.items()}
    for a in AXES:
        values[f"axis.{a}"].update(min_mm=-1e12, max_mm=1e12)
    return Machine(values, machine.tools, machine.source, machine.source_is_file)


def move(driver: Driver, machine: Machine, free: Machine, axis: int, distance_mm: float, rate: float):
    """One G91 G1 move of `axis` by distance_mm at `rate` mm/min: the run's Outcome."""
    text = f"G21 G91 G1 {AXES[axis].upper()}{distance_mm:.6f} F{rate:.6f}\n"
    _, compiled = compile_text(text, free, start_steps=read_position(driver), saved={})
    stream = encode_program(compiled.commands, compile_build())
    configure(driver, machine.timing(), compiled.settings)
    return run_program(driver, stream, len(compiled.commands))


def switch_active(driver: Driver, axis: int) -> bool:
    return bool(driver.read_register("INPUTS") >> (1 + axis) & 1)


def expect_switch(outcome, axis: int, what: str) -> None:
    """The move must have ended on this axis's limit switch."""
    name = AXES[axis].upper()
    if outcome.status == "error" and outcome.error == 17 and outcome.limits == 1 << axis:
        return
    if outcome.status == "error" and outcome.error == 17:
        others = " ".join(AXES[a].upper() for a in range(3) if outcome.limits >> a & 1)
        raise HomingError(f"{name}: the {others} limit switch tripped during the {what}")
    if outcome.status == "error":
        raise HomingError(f"{name}: controller error {outcome.error} ({p.error_text(outcome.error)}) during the {what}")
    raise HomingError(f"{name}: no limit switch was found during the {what}")


def expect_released(driver: Driver, outcome, axis: int, machine: Machine) -> None:
    name = AXES[axis].upper()
    if outcome.status != "done":
        raise HomingError(f"{name}: the pull-off did not end (controller error {outcome.error})")
    if switch_active(driver, axis):
        raise HomingError(f"{name}: the limit switch is still active after the pull-off of "
                          f"{machine.homing['pull_off_mm']:g} mm: raise homing.pull_off_mm")


def home_axis(driver: Driver, machine: Machine, axis: int) -> tuple[float, float]:
    """Home one axis: (the switch's machine coordinate, where the axis ends), mm."""
    name, settings = AXES[axis].upper(), machine.values[f"axis.{AXES[axis]}"]
    homing, free = machine.homing, unlimited(machine)
    toward = -1.0 if settings["home"] == "min" else 1.0
    pull_off = homing["pull_off_mm"]
    if switch_active(driver, axis):
        raise HomingError(f"{name}: the limit switch is active before the seek: move the axis off it, then home")
    seek = SEEK_TRAVELS * (settings["max_mm"] - settings["min_mm"]) + pull_off
    expect_switch(move(driver, machine, free, axis, toward * seek, homing["seek_mm_min"]), axis,
                  f"seek ({seek:g} mm towards {settings['home']})")
    expect_released(driver, move(driver, machine, free, axis, -toward * pull_off, homing["seek_mm_min"]), axis,
                    machine)
    expect_switch(move(driver, machine, free, axis, toward * 2 * pull_off, homing["locate_mm_min"]), axis,
                  f"slow approach ({2 * pull_off:g} mm)")
    switch_mm = settings["min_mm"] if toward < 0 else settings["max_mm"]
    driver.write_register("CONTROL", p.CONTROL_CLEAR | p.CONTROL_ENABLE)
    steps = round(switch_mm * machine.steps_per_mm[axis])
    driver.write_register(f"POS_{name}", steps & 0xFFFFFFFF)
    if read_position(driver)[axis] != steps:
        raise HomingError(f"{name}: the controller did not take the position (it was busy)")
    expect_released(driver, move(driver, machine, free, axis, -toward * pull_off, homing["seek_mm_min"]), axis,
                    machine)
    return switch_mm, read_position(driver)[axis] / machine.steps_per_mm[axis]


def axes_to_home(args, machine: Machine) -> list[int]:
    axes = machine.homed_axes()
    if args.axes is not None:
        chosen = args.axes.lower()
        if not chosen or any(a not in AXES for a in chosen):
            raise UsageError(f"--axes {args.axes}: give axes of XYZ, e.g. --axes Z or --axes XY")
        missing = [a.upper() for a in chosen if AXES.index(a) not in axes]
        if missing:
            raise UsageError(f"--axes {args.axes}: {' '.join(missing)} has no home end in the machine file "
                             f"(axis.{missing[0].lower()}.home) or is not in homing.order")
        axes = [a for a in axes if AXES[a] in chosen]
    if not axes:
        raise UsageError(f"{machine.source}: no axis to home: set axis.X.home = \"min\" or \"max\" (and homing.order)")
    return axes


def cmd_home(args) -> int:
    args.steps = args.line_noise = None
    check_link_args(args)
    if args.sim:
        raise UsageError("interp home: --sim has no limit switches to home to; use --port")
    machine = load_machine(args.machine, [], None)
    axes = axes_to_home(args, machine)
    try:
        transport, baud = send.open_transport(args, machine)     # (looked up: tests replace it)
    except LinkError as err:
        print(f"interp: error: link: {err}", file=sys.stderr)
        return 1
    driver = None
    try:
        driver = Driver(transport, baud=baud)
        driver.connect()
        check_controller(driver, compile_build(), machine.clock_hz)
        check_idle(driver)
        start = driver.clock()
        for axis in axes:
            switch_mm, end_mm = home_axis(driver, machine, axis)
            print(f"homed {AXES[axis].upper()}: switch at {switch_mm:.3f} mm, now at {end_mm:.3f} mm")
        print(f"machine position {mm_text(machine, read_position(driver))} mm "
              f"({driver.clock() - start:.3f} s)")
    except MismatchError as err:
        raise UsageError(str(err)) from None
    except HomingError as err:
        print(f"interp: error: homing {err}", file=sys.stderr)
        return 1
    except LinkError as err:
        print(f"interp: error: link: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        if driver is not None:
            driver.drop_stream()
            driver.write_register("CONTROL", p.CONTROL_ABORT | p.CONTROL_ENABLE)
        print("interp: interrupted: the controller was told to abort", file=sys.stderr)
        return 1
    finally:
        transport.close()
    return 0


def add_parser(sub) -> None:
    p_ = sub.add_parser("home", help="the homing cycle: each axis to its limit switch, which sets its position")
    add_link_options(p_, "refused: the simulated controller has no limit switches")
    p_.add_argument("--axes", metavar="XYZ", help="home only these axes (default: every axis with a home end)")
    p_.set_defaults(func=cmd_home)
