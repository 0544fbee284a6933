# SPDX-License-Identifier: Apache-2.0
"""The parameter file: the settings that outlive a program, as LinuxCNC's var file keeps them.

    saved = read_parameters(Path("mill.var"))     # {} when the file does not exist yet
    program = interpret(text, saved=saved)        # the program starts with them
    write_parameters(Path("mill.var"), program.saved)

One parameter a line, its number and its value separated by white space
("5221	12.5"), as LinuxCNC writes its var file; blank lines are skipped.  The
numbers are those of RS274NGC's persistent parameters this 3-axis machine has:
the G28 and G30 positions (#5161..#5163, #5181..#5183), the G92 offset and
whether it applies (#5211..#5213, #5210), the coordinate system in use (#5220)
and the nine coordinate systems' offsets (#5221 + 20 (n - 1) + axis, G54 ..
G59.3).  Lengths are machine millimetres.  A LinuxCNC var file is read too: its
other axes (A B C U V W) and rotations must be 0.  Anything else is an error of
one line naming the file and the line.
"""
from __future__ import annotations

import math
import os
from pathlib import Path

from ..cores import UsageError

AXES = "XYZ"
LINUXCNC_AXES = "XYZABCUVW"
LENGTH_LIMIT = 1e7                  # mm, as the machine file's travel
COORDINATE_SYSTEMS = ("G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3")


def offset_number(system: int, axis: int) -> int:
    """The parameter of coordinate system `system` (1 = G54 .. 9 = G59.3), axis 0..2."""
    return 5221 + 20 * (system - 1) + axis


LENGTHS = tuple([5161 + a for a in range(3)] + [5181 + a for a in range(3)] + [5211 + a for a in range(3)]
                + [offset_number(n, a) for n in range(1, 10) for a in range(3)])
SAVED = tuple(sorted(LENGTHS + (5210, 5220)))


def _meaning(number: int) -> str | None:
    """What a LinuxCNC persistent parameter this machine does not have is, or None."""
    for base, name in ((5161, "G28 position"), (5181, "G30 position"), (5211, "G92 offset")):
        if base <= number < base + 9:
            return f"the {name} of axis {LINUXCNC_AXES[number - base]}"
    if 5221 <= number <= 5390:
        system, index = divmod(number - 5221, 20)
        if index == 9:
            return f"the {COORDINATE_SYSTEMS[system]} rotation"
        if index < 9:
            return f"the {COORDINATE_SYSTEMS[system]} offset of axis {LINUXCNC_AXES[index]}"
    return None


def _value(where: str, number: int, value: float) -> float:
    if number == 5220:
        if value != int(value) or not 1 <= value <= 9:
            raise UsageError(f"{where}: #5220 (the coordinate system) must be 1 .. 9 (got {value:g})")
    elif number == 5210:
        if value not in (0.0, 1.0):
            raise UsageError(f"{where}: #5210 (G92 applies) must be 0 or 1 (got {value:g})")
    elif abs(value) > LENGTH_LIMIT:
        raise UsageError(f"{where}: #{number} must be within +-{LENGTH_LIMIT:g} mm (got {value:g})")
    return value


def read_parameters(path: Path) -> dict[int, float]:
    """The saved parameters {number: value} of the file at `path`; {} if it does not exist."""
    try:
        text = Path(path).read_bytes().decode("utf-8-sig")
    except FileNotFoundError:
        return {}
    except (OSError, ValueError) as err:
        if isinstance(err, UnicodeDecodeError):
            raise UsageError(f"{path}: not UTF-8 text (byte {err.start})") from None
        raise UsageError(f"cannot read parameter file {path}: {getattr(err, 'strerror', None) or err}") from None
    values: dict[int, float] = {}
    for index, line in enumerate(text.splitlines(), 1):
        where = f"{path} line {index}"
        fields = line.split()
        if not fields:
            continue
        if len(fields) != 2:
            raise UsageError(f"{where}: want a parameter number and its value (got {line.strip()[:40]!r})")
        try:
            number, value = int(fields[0]), float(fields[1])
        except ValueError:
            raise UsageError(f"{where}: want a parameter number and its value (got {line.strip()[:40]!r})") from None
        if not math.isfinite(value):
            raise UsageError(f"{where}: #{number} must be a finite number (got {fields[1]})")
        if number in values:
            raise UsageError(f"{where}: #{number} is given twice")
        if number not in SAVED:
            meaning = _meaning(number)
            if meaning is None:
                raise UsageError(f"{where}: #{number} is not a saved parameter (the file keeps #5161 .. #5390)")
            if value != 0.0:
                raise UsageError(f"{where}: #{number} ({meaning}) must be 0: this machine has axes X Y Z "
                                 "and no rotation")
            continue
        values[number] = _value(where, number, value)
    return values


def write_parameters(path: Path, values: dict[int, float]) -> None:
    """Write the saved parameters, in number order, replacing the file in one step (a run
    interrupted while writing leaves the old file)."""
    path = Path(path)
    lines = "".join(f"{number}\t{float(values[number])!r}\n" for number in SAVED if number in values)
    temporary = path.with_name(path.name + ".new")
    try:
        temporary.write_text(lines)
        os.replace(temporary, path)
    except (OSError, ValueError) as err:
        raise UsageError(f"cannot write parameter file {path}: {getattr(err, 'strerror', None) or err}") from None


def check_writable(path: Path) -> None:
    """UsageError unless the file can be written (its folder exists and is writable)."""
    folder = Path(path).parent
    try:
        ok = folder.is_dir() and os.access(folder, os.W_OK) and (not Path(path).exists() or os.access(path, os.W_OK))
    except (OSError, ValueError):
        ok = False
    if not ok:
        raise UsageError(f"cannot write parameter file {path}: its folder is missing or not writable")


def check_lengths(values: dict[int, float]) -> None:
    """UsageError when a program leaves a length the file cannot keep."""
    for number in LENGTHS:
        if abs(values.get(number, 0.0)) > LENGTH_LIMIT:
            raise UsageError(f"the program leaves #{number} at {values[number]:g} mm: a parameter file keeps "
                             f"at most +-{LENGTH_LIMIT:g} mm")


def describe(values: dict[int, float]) -> str:
    """The offsets in force at the start, for a person: "G55 X10 Y20 Z0 mm, G92 X0 Y0 Z-1 mm"
    ("" when none is set)."""
    parts = []
    system = int(values.get(5220, 1))
    offsets = [values.get(offset_number(system, a), 0.0) for a in range(3)]
    if system != 1 or any(offsets):
        parts.append(f"{COORDINATE_SYSTEMS[system - 1]} " + " ".join(f"{AXES[a]}{offsets[a] + 0.0:g}" for a in range(3))
                     + " mm")
    g92 = [values.get(5211 + a, 0.0) for a in range(3)]
    if values.get(5210) and any(g92):
        parts.append("G92 " + " ".join(f"{AXES[a]}{g92[a] + 0.0:g}" for a in range(3)) + " mm")
    return ", ".join(parts)
