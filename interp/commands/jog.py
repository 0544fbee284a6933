# SPDX-License-Identifier: Apache-2.0
"""`interp jog`: move the machine by hand (docs/host-driver.md, "Jogging").

  interp jog --port DEVICE [--baud B] [--machine FILE.toml] [--feed MM_MIN] [X10 Y-2.5 Z1]

With axis words: one relative move by that many mm at --feed (default 1000 mm/min, capped
by the axes' max_rate_mm_min as every feed is).  Without, on a terminal: the keys of
LinuxCNC's Axis, each key press one jog of the current increment:

  left / right   X- / X+          up / down   Y+ / Y-          Page Up / Page Down   Z+ / Z-
  [ / ]          smaller / larger increment (0.01, 0.1, 1, 10, 100 mm)
  q or Esc       quit             Ctrl-X      stop the jog that runs (on its path, then flushed)

A jog is compiled as `interp gcode` compiles `G91 G1` from the controller's position, with
the machine file's travel limits: a jog beyond the travel is refused before anything moves.
Exit status: 0 done; 1 a controller error (the position is printed), a stopped jog or a
link error; 2 usage (bad words, beyond the travel, no words and no terminal).
"""
from __future__ import annotations

import re
import sys
import time

from ..cores import UsageError
from ..gcode.machine import AXES, Machine, load_machine
from ..link import protocol as p
from ..link.driver import Driver, LinkError, MismatchError, configure, read_position, run_program
from ..link.records import encode_program
from .gcode import compile_text
from . import send
from .send import Keyboard, add_link_options, key_tokens, check_link_args, compile_build, mm_text
from .status import work_position

DEFAULT_FEED = 1000.0                               # mm/min
INCREMENTS = (0.01, 0.1, 1.0, 10.0, 100.0)          # mm, the [ and ] keys
FIRST_INCREMENT = 2                                 # 1 mm
ARROWS = {"C": (0, 1), "D": (0, -1), "A": (1, 1), "B": (1, -1)}     # ESC [ C: right ...
PAGES = {"5": (2, 1), "6": (2, -1)}                                 # ESC [ 5 ~: Page Up ...
QUIT = ("q", "Q", "\x1b")
STOP = "\x18"                                       # Ctrl-X
KEYS_HELP = ("keys: arrows X/Y, Page Up/Down Z, [ ] increment, q quit; Ctrl-X stops a jog")
WORD = re.compile(r"\s*([XYZxyz])\s*([-+]?(?:\d+\.?\d*|\.\d+))\s*")


def parse_words(words: list[str]) -> tuple[float, float, float]:
    """Axis words ("X10", "Y-2.5", or "X10Y-2.5" in one) -> (dx, dy, dz) mm; UsageError naming
    the first word that is not one."""
    text, at, delta, seen = "".join(w + " " for w in words), 0, [0.0, 0.0, 0.0], set()
    while at < len(text.rstrip()):
        match = WORD.match(text, at)
        if match is None:
            bad = text[at:].split()[0]
            raise UsageError(f"jog: {bad}: give axis words in mm, e.g. X10 Y-2.5")
        axis = "xyz".index(match.group(1).lower())
        if axis in seen:
            raise UsageError(f"jog: {match.group(1).upper()} given twice")
        seen.add(axis)
        delta[axis] = float(match.group(2))
        at = match.end()
    return tuple(delta)


def unlimited(machine: Machine, axes=range(3)) -> Machine:
    """The machine without the travel limits of `axes` (homing: the position is not known yet;
    a jog: an axis not homed since the controller's reset)."""
    values = {section: dict(keys) for section, keys in machine.values.items()}
    for a in axes:
        values[f"axis.{AXES[a]}"].update(min_mm=-1e12, max_mm=1e12)
    return Machine(values, machine.tools, machine.source, machine.source_is_file)


def relative_move(driver: Driver, machine: Machine, limits: Machine, delta_mm, rate: float, keys=None):
    """One G91 G1 move by delta_mm (x, y, z) at `rate` mm/min, compiled with `limits`' travel (home:
    a machine without limits) from the controller's position: the run's Outcome."""
    words = " ".join(f"{a}{d:.6f}" for a, d in zip("XYZ", delta_mm) if d)
    _, compiled = compile_text(f"G21 G91 G1 {words} F{rate:.6f}\n", limits, start_steps=read_position(driver),
                               saved={})
    configure(driver, machine.timing(), compiled.settings, compiled)
    return run_program(driver, encode_program(compiled.commands, compile_build(), codes=compiled),
                       len(compiled.commands),
                       keys=keys)


def travel(driver: Driver, machine: Machine) -> Machine:
    """The machine whose travel limits a jog keeps: those of the axes whose position was set
    since the controller's reset (STATUS.position_set: homed), as Grbl keeps soft limits only
    once homed; an axis not homed yet jogs freely (to its switch, off it)."""
    homed = driver.read_register("STATUS") >> 16 & 7
    return unlimited(machine, [a for a in range(3) if not homed >> a & 1])


def jog(driver: Driver, machine: Machine, limits: Machine, delta_mm, rate: float, keys=None) -> tuple[str, str]:
    """Run one jog: (Outcome.status, what to say: "" when it ran to its end).  UsageError (one
    line, without the G-code line number) when it is refused before anything moves: beyond the
    travel, or less than half a step on every axis."""
    if all(abs(d * spm) < 0.5 for d, spm in zip(delta_mm, machine.steps_per_mm)):
        raise UsageError("jog: less than half a step on every axis: nothing to move")
    try:
        outcome = relative_move(driver, machine, limits, delta_mm, rate, keys)
    except UsageError as err:
        raise UsageError("jog: " + re.sub(r"^line \d+: ", "", str(err))) from None
    if outcome.status == "done":
        return "done", ""
    if outcome.status == "error":
        return "error", f"controller error {outcome.error} ({p.error_text(outcome.error)})"
    return outcome.status, "the jog was stopped" + (f" ({outcome.message})" if outcome.message else "")


def show_position(driver: Driver, machine: Machine, said: str = "") -> None:
    """The machine position (and what the jog said), then with a parameter file the work position."""
    position = read_position(driver)
    print(f"machine position {mm_text(machine, position)} mm" + (f": {said}" if said else ""))
    work = work_position(machine, position)
    if work:
        print(work)


def unfinished(typed: str) -> bool:
    """The keys end inside an escape sequence (its bytes can come in two reads over ssh)."""
    return re.search(r"\x1b(\[[0-9;]*|O)?$", typed) is not None


def key_jog(token: str):
    """(axis, sign) of a jog key, or None."""
    if len(token) == 3 and token[:2] in ("\x1b[", "\x1bO"):
        return ARROWS.get(token[2])
    if len(token) == 4 and token.startswith("\x1b[") and token.endswith("~"):
        return PAGES.get(token[2])
    return None


def read_keys(keyboard) -> str:
    """The keys typed; an escape sequence cut between two reads is completed (50 ms)."""
    typed = keyboard()
    if typed and unfinished(typed):
        time.sleep(0.05)
        typed += keyboard()
    return typed


def interactive(driver: Driver, machine: Machine, rate: float, keyboard, jog_keys=None) -> int:
    """The keys' loop: 0 when quit (q, Esc, or Ctrl-C between jogs), 1 after a controller error.
    keyboard() -> the keys typed since the last call; jog_keys() -> those typed during a jog
    (default: keyboard's, of which only Ctrl-X counts: a key held down repeats, and its jogs
    must not pile up).  Ctrl-X stops a jog (on its path, then flushed) and the loop goes on."""
    if jog_keys is None:
        def jog_keys() -> str:
            return STOP if STOP in keyboard() else ""
    increment = FIRST_INCREMENT
    limits = travel(driver, machine)
    print(f"interp jog: increment {INCREMENTS[increment]:g} mm at {rate:g} mm/min; {KEYS_HELP}", file=sys.stderr)
    while True:
        try:
            tokens = key_tokens(read_keys(keyboard))
            if not tokens:
                time.sleep(0.02)
                continue
        except KeyboardInterrupt:                       # Ctrl-C while nothing moves: quit
            return 0
        for token in tokens:
            if token in QUIT:
                return 0
            if token in "[]":
                increment = max(0, min(len(INCREMENTS) - 1, increment + (1 if token == "]" else -1)))
                print(f"interp jog: increment {INCREMENTS[increment]:g} mm", file=sys.stderr)
                continue
            move = key_jog(token)
            if move is None:
                continue
            axis, sign = move
            delta = [0.0, 0.0, 0.0]
            delta[axis] = sign * INCREMENTS[increment]
            try:
                status, said = jog(driver, machine, limits, delta, rate, jog_keys)
            except UsageError as err:                   # beyond the travel: nothing moved
                print(f"interp: {err}", file=sys.stderr)
                break
            show_position(driver, machine, said)
            if status == "error":
                return 1
            break                                       # keys typed ahead of the jog are dropped


def cmd_jog(args) -> int:
    args.steps = args.line_noise = None
    check_link_args(args)
    if not args.feed > 0 or args.feed > 1e7:
        raise UsageError(f"--feed {args.feed:g}: give mm/min > 0, at most 1e7")
    delta = parse_words(args.move)
    keys_wanted = not args.move
    if keys_wanted and not (sys.stdin.isatty() and sys.stderr.isatty()):
        raise UsageError("interp jog: give the move (e.g. X10 Y-2.5), or run it on a terminal for the keys")
    if not keys_wanted and not any(delta):
        raise UsageError("jog: every axis word is 0: nothing to move")
    machine = load_machine(args.machine, [], None)
    opened = send.open_or_report(args, machine)
    if opened is None:
        return 1
    transport, baud = opened
    driver = keyboard = None
    try:
        driver = Driver(transport, baud=baud)
        send.make_ready(driver, machine, args.sim)
        send.warn_of_stop(driver, "interp jog")
        if keys_wanted:
            keyboard = Keyboard(True)
            return interactive(driver, machine, args.feed, keyboard)
        status, said = jog(driver, machine, travel(driver, machine), delta, args.feed)
        show_position(driver, machine)
        if said:
            print(f"interp: error: {said}", file=sys.stderr)
            return 1
        return 0
    except MismatchError as err:
        raise UsageError(str(err)) from None
    except (LinkError, send.NotHomed) as err:
        print(f"interp: error: {'link: ' if isinstance(err, LinkError) else ''}{err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return send.interrupted(driver)
    finally:
        if keyboard is not None:
            keyboard.close()
        transport.close()


def add_parser(sub) -> None:
    p_ = sub.add_parser("jog", help="move the machine by hand: one relative move, or the arrow keys")
    add_link_options(p_, "the Verilator model of the controller instead of a port")
    p_.add_argument("--feed", type=float, default=DEFAULT_FEED, metavar="MM_MIN",
                    help=f"jog speed, mm/min (default {DEFAULT_FEED:g}; capped by the axes' max_rate_mm_min)")
    p_.add_argument("move", nargs="*", metavar="WORD",
                    help="axis words of one relative move in mm, e.g. X10 Y-2.5 (none: the keys, on a terminal)")
    p_.set_defaults(func=cmd_jog)
