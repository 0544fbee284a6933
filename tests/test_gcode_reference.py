# SPDX-License-Identifier: Apache-2.0
"""The tests' own G-code reading (interp.testing.gcode_reference) on small programs
whose end positions were worked out by hand."""
import importlib.util
import os
import random

import pytest

from interp.testing.gcode_reference import Refused, run

CASES = [
    # (program, end in work coordinates (program units), end in machine mm)
    ("G20 G0 X1 Y2 Z3", (1, 2, 3), (25.4, 50.8, 76.2)),
    ("G20 G0 X1\nG21 G0 Y10", (25.4, 10, 0), (25.4, 10, 0)),
    ("G91 G0 X1 Y1\nX1\nG90 X5", (5, 1, 0), (5, 1, 0)),
    ("G0 X10\nG92 X0\nG0 X5", (5, 0, 0), (15, 0, 0)),
    ("G0 X10\nG92 X0\nG92.1", (10, 0, 0), (10, 0, 0)),
    ("G0 X10\nG92 X0\nG92.2\nG92.3", (0, 0, 0), (10, 0, 0)),
    ("G10 L2 P1 X100\nG54 G0 X1", (1, 0, 0), (101, 0, 0)),
    ("G10 L2 P1 X100\nG0 X1\nG10 L20 P2 X0\nG55", (0, 0, 0), (101, 0, 0)),
    ("G10 L2 P1 X100\nG0 X1\nG53 G0 X0", (-100, 0, 0), (0, 0, 0)),
    ("G20 G10 L2 P3 Y1\nG56 G0 Y1", (0, 1, 0), (0, 50.8, 0)),
    ("G0 X1\nG2 X-1 Y0 I-1 J0 F100", (-1, 0, 0), (-1, 0, 0)),
    ("G0 X1\nG3 X1 Y0 Z-2 I-1 J0 P3 F100", (1, 0, -2), (1, 0, -2)),
    ("G18 G0 X1\nG2 X0 Z1 R1 F100", (0, 0, 1), (0, 0, 1)),
    ("G0 X0 Y0 Z10\nG98 G81 X1 Y1 Z-2 R2 F100\nX2\nG80", (2, 1, 10), (2, 1, 10)),
    ("G0 X0 Y0 Z10\nG99 G81 X1 Y1 Z-2 R2 F100\nX2\nG80", (2, 1, 2), (2, 1, 2)),
    ("G0 Z-1\nG98 G82 X1 Z-2 R2 P1 F100", (1, 0, 2), (1, 0, 2)),
    ("G0 X0 Y0 Z5\nG91 G81 X1 Y2 Z-3 R-2 L3 F100", (3, 6, 3), (3, 6, 3)),
    ("G20 G0 X1.5 Y0 Z0\nG91 G81 R.1 Z-.5 ^60 L6 F10", (1.5, 0, 0.1), (38.1, 0, 2.54)),
    ("G20 G0 X1.5 Y0 Z0\nG91 G81 R.1 Z-.5 ^90 L1 F10", (0, 1.5, 0.1), (0, 38.1, 2.54)),
    ("G1 F100 @2 ^90", (0, 2, 0), (0, 2, 0)),
    ("G0 X2\nG91 G1 F100 @-1 ^180", (-1, 0, 0), (-1, 0, 0)),
    ("G0 X5 Y5 Z5\nG28 Z10", (5, 5, 3), (5, 5, 3)),
    ("G0 X5 Y5 Z5\nG28", (1, 2, 3), (1, 2, 3)),
    ("G0 X5 Y5 Z5\nG30 X6", (7, 5, 5), (7, 5, 5)),
    ("G0 X5\nG28.1\nG0 X0\nG28", (5, 0, 0), (5, 0, 0)),
    ("T1 M6\nG43 H1\nG0 Z5", (0, 0, 5), (0, 0, 15)),
    ("T1 M6\nG43\nG0 Z5\nG49", (0, 0, 15), (0, 0, 15)),
    ("#1 = [2 + 3 * 4 ** 2]\nG0 X#1", (50, 0, 0), (50, 0, 0)),
    ("G0 X[ATAN[1]/[1]] Y[2 ** 3 ** 2] Z[8 - 2 - 1]", (45, 64, 5), (45, 64, 5)),
    ("G0 X[-7 MOD 3] Y[7 MOD -3] Z[FIX[-1.5] + FUP[-1.5] * 10]", (2, 1, -12), (2, 1, -12)),
    ("G0 X[ROUND[2.5]] Y[SQRT[16] + ABS[-1]] Z[[1 LT 2] + [2 EQ 3] * 4]", (3, 5, 1), (3, 5, 1)),
    ("G0 X[SIN[30] * 2] Y[COS[60] * 4] Z[EXP[LN[3]]]", (1, 2, 3), (1, 2, 3)),
    ("G0 X[1 AND 0] Y[1 OR 0] Z[1 XOR 1]", (0, 1, 0), (0, 1, 0)),
    ("#1=1\n#1=2 G0 X#1\nG0 Y#1", (1, 2, 0), (1, 2, 0)),
    ("#2=3\n#[#2]=7\nG0 X#3 Y##2", (7, 7, 0), (7, 7, 0)),
    ("#<a>=2\n#<_g>=3\nG0 X[#<a>*#<_g>] Y[EXISTS[#<a>]] Z[EXISTS[#<b>]]", (6, 1, 0), (6, 1, 0)),
    ("#<Two Words> = 4\nG0 X#<twowords>", (4, 0, 0), (4, 0, 0)),
    ("G0 X3\nG0 Y#5420 Z[#5421 + 1]", (3, 3, 1), (3, 3, 1)),
    ("o100 sub\nG0 X#1 Y#2\no100 endsub\no100 call [3] [4]\nG0 Z#1", (3, 4, 0), (3, 4, 0)),
    ("o<s> sub\n#<v> = 1\no<s> return\nG0 X9\no<s> endsub\no<s> call\nG0 Y5", (0, 5, 0), (0, 5, 0)),
    ("#1=0\no1 while [#1 LT 5]\n#1=[#1+1]\no1 endwhile\nG0 X#1", (5, 0, 0), (5, 0, 0)),
    ("o2 repeat [3]\nG91 G0 X1\no2 endrepeat", (3, 0, 0), (3, 0, 0)),
    ("#1=0\no3 do\n#1=[#1+2]\no3 while [#1 LT 5]\nG0 X#1", (6, 0, 0), (6, 0, 0)),
    ("#1=0\no4 while [1]\n#1=[#1+1]\no5 if [#1 EQ 3]\no4 break\no5 endif\no4 endwhile\nG0 X#1",
     (3, 0, 0), (3, 0, 0)),
    ("#1=2\no6 if [#1 EQ 1]\nG0 X1\no6 elseif [#1 EQ 2]\nG0 X2\no6 else\nG0 X3\no6 endif",
     (2, 0, 0), (2, 0, 0)),
    ("#1=5\no6 if [#1 EQ 1]\nG0 X1\no6 elseif [#1 EQ 2]\nG0 X2\no6 else\nG0 X3\no6 endif",
     (3, 0, 0), (3, 0, 0)),
    ("G0 X1\nM2\nG0 X5", (1, 0, 0), (1, 0, 0)),
    ("G0 X1\nM30\nG0 X5", (1, 0, 0), (1, 0, 0)),
    ("%\n(a (nested) comment) G0 X1 ; G0 X9\n%", (1, 0, 0), (1, 0, 0)),
    ("N10 G0 X1\nN20 Y2 (modal G0)\nO1000\nn30\tz3", (1, 2, 3), (1, 2, 3)),
    ("g0x1y2\ng1 f10 z-1", (1, 2, -1), (1, 2, -1)),
    ("$H\n?\nG0 X1", (1, 0, 0), (1, 0, 0)),
    ("G0 X1\r\r\nG0 Y2\r\n", (1, 2, 0), (1, 2, 0)),
]


@pytest.mark.parametrize("program, work, machine", CASES)
def test_end_position(program, work, machine):
    result = run(program, g28=(1, 2, 3), g30=(7, 8, 9), tools={1: {"length_mm": 10.0}})
    assert result.work == pytest.approx(work, abs=1e-9)
    assert result.machine == pytest.approx(machine, abs=1e-9)


def test_counts_and_units():
    result = run("G20\nG0 X1\nG1 X2 F10\nG2 X3 R0.5\nG3 X3 I-1\nG91 G81 X1 Z-1 R1 L2\nM2")
    assert (result.units, result.arcs) == ("inch", 2)
    # the cycle: up to R once, then per hole: to the hole, feed, retract
    assert result.lines == 2 + 1 + 2 * 3
    assert result.work == pytest.approx((5, 0, 1))
    assert run("G0 X1").units == "mm"


def test_events_in_order():
    result = run("S1000 M3\nS2000\nS2000\nS0 M5\nS10\nM8\nM9\nT2 M6\nM62 P1\nM0\nM2")
    assert result.events == [
        ("spindle_cw", 1000), ("spindle_speed", 2000), ("spindle_off", 0), ("flood_on", 0),
        ("coolant_off", 0), ("tool_change", 2), ("pause", 6), ("output_on", 1), ("pause", 0),
        ("program_end", 2)]


@pytest.mark.parametrize("program, line", [
    ("G0 X1\nG41 D1 G1 X2", 2),                     # cutter radius compensation
    ("G81 X1 Z-1 R1 F10\nG80\nX2", 3),              # axis words with G80 in force
    ("G0 G80 X1", 1),                               # two motion codes
    ("G0 X1\nG2 X1 R1 F10", 2),                     # full circle in R format
    ("G1 X1", 1),                                   # feed zero
    ("G0 X#<nothing>", 1),                          # undefined named parameter
    ("G0 X[1/0]", 1),
    ("M140 S60", 1),
    ("G5 X1", 1),
    ("G1 E3 F10", 1),
    ("(unclosed", 1),
    ("o1 call", 1),
    ("G1 F10 X1\nG81 X1 R1 F10", 2),                # first cycle block without Z
    ("G0 Z5\nG81 X1 Z6 R2 F10", 2),                 # R below the bottom
    ("G10 L1 P1 Z1", 1),
    ("G0 X1\r\r\nG0 Y2\r\r\nG41 D1", 3),           # lines counted by their line feeds
])
def test_refusals(program, line):
    with pytest.raises(Refused) as error:
        run(program)
    assert error.value.line == line


def test_fanuc_g80_habits():
    program = "G0 G80 X1\nG0 Z5\nG98 G81 X2 Z-1 R1 F10\nG80\nZ7\nX3"
    with pytest.raises(Refused):
        run(program)
    assert run(program, fanuc_g80=True).work == pytest.approx((3, 0, 7))
    with pytest.raises(Refused) as error:                # no G0 / G1 before the cycle
        run("G2 X1 I1 F10\nG81 X2 Z-1 R1\nG80\nZ7", fanuc_g80=True)
    assert error.value.line == 4


# ---------------------------------------------------------------------------- against the front end
def random_program(rng: random.Random) -> str:
    """A random program of the features whose end the reference knows, all valid."""
    def num(low=-20.0, high=20.0):
        return f"{rng.uniform(low, high):.4f}"
    lines = [rng.choice(["G21", "G20"]), "F100", rng.choice(["G98", "G99"])]
    for n in range(1, 4):
        lines.append(f"G10 L2 P{n} X{num()} Y{num()} Z{num(-5, 5)}")
    lines.append(rng.choice(["G54", "G55", "G56"]))
    for _ in range(rng.randrange(5, 25)):
        kind = rng.randrange(12)
        distance = rng.choice(["G90", "G91"])
        if kind <= 2:
            lines.append(f"{distance} G{rng.choice([0, 1])} X{num()} Y{num()} Z{num(-5, 5)}")
        elif kind == 3:                     # an arc about a random centre, maybe a helix
            radius, start = rng.uniform(1, 10), rng.uniform(0, 360)
            sweep = rng.uniform(-300, 300)
            centre = [f"[#5420 - {radius} * COS[{start}]]", f"[#5421 - {radius} * SIN[{start}]]"]
            lines.append(f"#1 = {centre[0]} #2 = {centre[1]}")
            end = start + sweep
            lines.append(f"G90 G{2 if sweep < 0 else 3} X[#1 + {radius} * COS[{end}]] "
                         f"Y[#2 + {radius} * SIN[{end}]] Z{num(-5, 5)} "
                         f"I[{radius} * COS[{start}] * -1] J[{radius} * SIN[{start}] * -1]")
        elif kind == 4:                     # R form in the plane of G18 or G19
            plane, (u, v) = rng.choice([("G18", "ZX"), ("G19", "YZ"), ("G17", "XY")])
            lines.append(f"{plane} G91 G{rng.choice([2, 3])} {u}{num(1, 5)} {v}{num(1, 5)} "
                         f"R{num(6, 9)}")
            lines.append("G17 G90")
        elif kind == 5:
            lines.append(f"G92 X{num()} Z{num(-5, 5)}" if rng.random() < 0.7 else "G92.1")
        elif kind == 6:
            lines.append(f"G90 G53 G0 X{num()} Y{num()}")
        elif kind == 7:                     # a canned cycle, absolute or incremental, repeated
            cycle = rng.choice(["G81", "G82 P0.1", "G83 Q1", "G73 Q0.5", "G85", "G89 P0.2"])
            if distance == "G90":
                lines.append(f"G90 G0 Z{num(5, 10)}")
                lines.append(f"G90 {cycle} X{num()} Y{num()} Z{num(-5, -1)} R{num(1, 4)}")
                lines.append(f"X{num()}")
            else:
                lines.append(f"G91 {cycle} X{num(-3, 3)} Y{num(-3, 3)} Z{num(-6, -1)} "
                             f"R{num(-2, 2)} L{rng.randrange(1, 5)}")
            lines.append("G80")
        elif kind == 8:
            lines.append(f"#<_v> = [{num()} * 2 + #5422 / 4]")
            lines.append("G90 G1 Z#<_v> X[#5420 + 1]")
        elif kind == 9:
            label = len(lines)
            lines.append(f"o{label} repeat [{rng.randrange(1, 4)}]")
            lines.append(f"G91 G1 X{num(-2, 2)} Y{num(-2, 2)}")
            lines.append(f"o{label} endrepeat")
        elif kind == 10:
            lines.append(rng.choice(["G28", f"G28 Z{num(-5, 5)}", "G30", f"G30 X{num()}"]))
        else:
            lines.append(rng.choice(["G20", "G21", "G54", "G55", "G56", "G92.2", "G92.3"]))
    lines.append(rng.choice(["M2", "M30", ""]))
    return "\n".join(lines) + "\n"


SEEDS = [int(s) for s in os.environ.get("GCODE_REFERENCE_SEEDS", "").split(",") if s] or \
    list(range(40))


@pytest.mark.skipif(importlib.util.find_spec("interp.gcode.interpreter") is None,
                    reason="the G-code front end (interp.gcode.interpreter) is not here")
@pytest.mark.parametrize("seed", SEEDS)
def test_random_program_agrees_with_front_end(seed):
    from interp.gcode.interpreter import interpret

    program = random_program(random.Random(seed))
    print(f"seed {seed} (GCODE_REFERENCE_SEEDS={seed} repeats it):\n{program}")
    homes = {"g28": (1.0, -2.0, 3.0), "g30": (-4.0, 5.0, -6.0)}
    front, expected = interpret(program, **homes), run(program, **homes)
    assert front.end_work == pytest.approx(expected.work, abs=1e-6)
    assert front.end_machine == pytest.approx(expected.machine, abs=1e-6)
    assert front.units == expected.units
