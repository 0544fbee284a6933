# SPDX-License-Identifier: Apache-2.0
"""The G-code interpreter's machine semantics (RS274NGC as LinuxCNC runs it): text -> moves in
machine mm.  Each accepted feature, the exact message of each refused or malformed case, random
programs against an independent model of the position, and the public corpus end to end."""
import math
import os
import random
import time
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interp.cores import UsageError
from interp.gcode.errors import GcodeError
from interp.gcode.interpreter import interpret
from interp.gcode.moves import EVENTS, Arc, Dwell, Event, Line

ROOT = Path(__file__).resolve().parents[1]
INCH = 25.4


def moves(text, **kw):
    return interpret(text, **kw).moves


def paths(text, **kw):
    return [m for m in moves(text, **kw) if isinstance(m, (Line, Arc))]


def ends(text, **kw):
    return [tuple(round(c, 6) for c in m.end) for m in paths(text, **kw)]


def error(text, **kw):
    with pytest.raises(GcodeError) as info:
        interpret(text, **kw)
    return str(info.value)


def close(a, b, tol=1e-9):
    return all(abs(x - y) <= tol for x, y in zip(a, b, strict=True))


def continuous(program):
    previous = (0.0, 0.0, 0.0)
    for move in program.moves:
        if isinstance(move, (Line, Arc)):
            if move.start != previous:
                return False
            previous = move.end
    return previous == tuple(program.end_machine)


# ---- straight moves, modes, units ---------------------------------------------------------

def test_rapid_feed_and_modal_motion():
    ms = paths("G0 X10 Y5\nG1 X20 F100\nY10\nG0 Z3")
    assert [(m.end, m.feed, m.line) for m in ms] == [
        ((10, 5, 0), None, 1), ((20, 5, 0), 100, 2), ((20, 10, 0), 100, 3), ((20, 10, 3), None, 4)]


def test_error_is_a_usage_error_with_the_exact_format():
    with pytest.raises(UsageError) as info:
        interpret("G1 X10")
    assert str(info.value) == "line 1, column 1: G1: feed move without a feed rate (no F word yet)"


@pytest.mark.parametrize("text,message", [
    ("G1 G0 X10 F100",
     "line 1, column 4: G0: two G codes of the motion group in one block (G1 and G0)"),
    ("G81 G80 X10", "line 1, column 5: G80: two G codes of the motion group in one block "
                    "(G81 and G80)"),
    ("G20 G21", "line 1, column 5: G21: two G codes of the units group in one block (G20 and G21)"),
    ("M3 M5", "line 1, column 4: M5: two M codes of the spindle group in one block (M3 and M5)"),
    ("X10", "line 1, column 1: X10: axis word without a motion mode (G0, G1, G2, G3 or a cycle) "
            "in force"),
    ("G0 X1\nG80 X10", "line 2, column 1: G80: axis words cannot be used with G80"),
    ("G0 X1 X2", "line 1, column 7: X2: two X words in one block"),
    ("G1 X1 F0", "line 1, column 7: F0: the feed rate must be positive"),
    ("G0 X1 E5", "line 1, column 7: E5: E is not an RS274NGC word"),
    ("G0 X1 I5", "line 1, column 7: I5: word not used by any command in this block"),
    ("G0 X1 D1", "line 1, column 7: D1: D word without G41, G42, G41.1 or G42.1"),
    ("G0 X1 H1", "line 1, column 7: H1: H word without G43"),
    ("G0 G28 X1", "line 1, column 1: G0: G28 and G0 both use the axis words"),
    ("G41 D1", "line 1, column 5: D1: tool 1 is not in the tool table: its diameter is not known"),
    ("G42.1 D1 G41", "line 1, column 10: G41: two G codes of the cutter compensation group in one block "
                     "(G42.1 and G41)"),
    ("G95", "line 1, column 1: G95: feed per revolution (G95) is not supported"),
    ("G38.5 Z-1", "line 1, column 1: G38.5: feed move without a feed rate (no F word yet)"),
    ("G5.3", "line 1, column 1: G5.3: NURBS moves (G5.3) are not supported"),
    ("G12", "line 1, column 1: G12: unknown or unsupported G code"),
    ("M300 S30", "line 1, column 1: M300: unsupported M code"),
    ("M140 S60", "line 1, column 1: M140: unsupported M code"),
    ("G0 A5", "line 1, column 4: A5: this machine has no A axis"),
    ("G4", "line 1, column 1: G4: needs a P word (seconds)"),
    ("G4 P-1", "line 1, column 4: P-1: the dwell time cannot be negative"),
    ("M62", "line 1, column 1: M62: needs a P word (the output number)"),
    ("M62 P1.5", "line 1, column 5: P1.5: the output number must be a whole number >= 0"),
    ("M65 P-1", "line 1, column 5: P-1: the output number must be a whole number >= 0"),
    ("G20 G0 X[10**308]", "line 1, column 8: X[10**308]: the value is out of range (beyond 1e+15)"),
    ("G[10**308]", "line 1, column 1: G[10**308]: the value is out of range (beyond 1e+15)"),
    ("G4 P[10**16]", "line 1, column 4: P[10**16]: the value is out of range (beyond 1e+15)"),
    ("G20\n#5221=[10**308]\nG54", "line 3, column 1: a position or offset is out of range (not a finite "
                                  "number)"),
    ("G53 G2 X1 I1 F10", "line 1, column 1: G53: G53 needs G0 or G1"),
    ("G91 G53 G0 X1", "line 1, column 5: G53: G53 cannot be used in incremental mode (G91)"),
    ("G92", "line 1, column 1: G92: G92 needs at least one axis word"),
    ("G10 L2 P10 X1", "line 1, column 8: P10: the coordinate system P must be 0 (the current "
                      "one) to 9"),
    ("G10 L2 P1 R45 X1", "line 1, column 11: R45: rotated coordinate systems are not supported"),
    ("G10 L3 P1 X1", "line 1, column 5: L3: unsupported G10 form (L1, L2, L10, L11 and L20 are "
                     "supported)"),
    ("G93 G1 X1", "line 1, column 5: G1: inverse time mode (G93) needs an F word on every feed "
                  "move"),
    ("G93 G1 X1 F2\nX2", "line 2, column 1: X2: inverse time mode (G93) needs an F word on every "
                         "feed move"),
])
def test_refused_and_malformed(text, message):
    assert error(text) == message


def test_axis_words_after_g80_move_in_the_mode_before_the_cycle_with_a_warning():
    program = interpret("G0 Z5\nG81 X1 Z-1 R2 F100\nG80\nZ10")
    assert program.moves[-1].end == (1, 0, 10) and program.moves[-1].feed is None
    assert program.warnings == [
        "line 4: Z10: axis word after G80: moved in G0, the motion mode in force before the "
        "canned cycle (as Fanuc and Mach3 do; LinuxCNC refuses it)"]


def test_fanuc_safe_start_g0_with_g80():
    assert ends("G0 G90 G40 G21 G17 G94 G80\nX1") == [(1, 0, 0)]
    assert ends("G80 G1 X1 F10") == [(1, 0, 0)]


def test_incremental_and_units():
    program = interpret("G20 G91 G1 X1 Y2 F10\nX1\nG21 G90 X10")
    assert ends("G20 G91 G1 X1 Y2 F10\nX1\nG21 G90 X10") == [
        (INCH, 2 * INCH, 0), (2 * INCH, 2 * INCH, 0), (10, 2 * INCH, 0)]
    assert [m.feed for m in program.moves] == [10 * INCH, 10 * INCH, 10 * INCH]
    assert program.units == "mm" and close(program.end_work, (10, 50.8, 0))
    inch = interpret("G20 G0 X1 Y2")
    assert inch.units == "inch" and close(inch.end_work, (1, 2, 0))
    assert close(inch.end_machine, (INCH, 2 * INCH, 0))


def test_units_take_effect_before_the_motion_of_their_block():
    # order of execution: G20/G21 (16) before the motion (24); F is read in the block's units
    assert ends("G1 X1 F10 G20") == [(INCH, 0, 0)]
    assert moves("G1 X1 F10 G20")[0].feed == 10 * INCH


def test_inverse_time_feed():
    ms = moves("G93 G1 X30 Y40 F2\nG3 X0 Y0 I-15 J-20 F4\nG94 G1 X1 F100")
    assert ms[0].feed == pytest.approx(50 * 2)              # 50 mm in 1/2 minute
    assert ms[1].feed == pytest.approx(math.pi * 25 * 4)    # half circle of radius 25
    assert ms[2].feed == 100


def test_inverse_time_leaves_the_feed_undefined():
    assert error("G1 X1 F100\nG93\nG94 G1 X2") == (
        "line 3, column 5: G1: feed move without a feed rate (no F word yet)")


# ---- work offsets, G92, G53, G28 / G30, parameters ---------------------------------------

def test_coordinate_systems_and_g10():
    program = interpret("G10 L2 P2 X10 Y20 Z5\nG55 G0 X0 Y0 Z0\nG10 L20 P2 X1\nG0 X0\n"
                        "G54 G0 X0\nG10 L2 P0 Z-1\nG0 Z0\nG59.3 X1")
    assert ends("G10 L2 P2 X10 Y20 Z5\nG55 G0 X0 Y0 Z0\nG10 L20 P2 X1\nG0 X0\n"
                "G54 G0 X0\nG10 L2 P0 Z-1\nG0 Z0\nG59.3 X1") == [
        (10, 20, 5), (9, 20, 5), (0, 20, 5), (0, 20, -1), (1, 20, -1)]
    assert close(program.end_work, (1, 20, -1))


def test_g92_family():
    text = "G0 X10 Y10\nG92 X0 Y0\nG0 X5\nG92.2\nG0 X5\nG92.3\nG0 X0\nG92.1\nG0 X1"
    assert ends(text) == [(10, 10, 0), (15, 10, 0), (5, 10, 0), (10, 10, 0), (1, 10, 0)]


def test_m70_m72_save_and_restore_the_modal_state():
    """M72 brings back what M70 saved: units, distance mode, F, S, spindle and coolant (with
    their events), plane, coordinate system, path control."""
    program = interpret("G1 F100\nM3 S1000 M8\nM70\nG91 G20 G18 G61 F10 S500 G55\nM5 M9\nX1\nM72\nX1\n"
                        "G2 X2 I0.5\nM2")
    moves = program.moves
    events = [(m.name, m.value, m.line) for m in moves if isinstance(m, Event)]
    assert events == [("spindle_cw", 1000, 2), ("flood_on", 0, 2), ("spindle_speed", 500, 4),
                      ("spindle_off", 0, 5), ("coolant_off", 0, 5), ("spindle_cw", 1000, 7), ("flood_on", 0, 7),
                      ("program_end", 2, 10)]
    lines = [m for m in moves if not isinstance(m, Event)]
    assert [(m.end, m.feed) for m in lines[:2]] == [((25.4, 0, 0), 254.0), ((1, 0, 0), 100.0)]
    assert lines[1].path_control == ("G64", None) and lines[0].path_control == ("G61", None)
    assert isinstance(lines[2], Arc) and lines[2].plane == "XY" and program.units == "mm"


def test_m73_restores_at_the_subroutines_return():
    """M73 in a subroutine: its modal state comes back when it returns (also when the return is
    the program's last block), at each level of nested calls."""
    text = ("o100 sub\nM73\nG91 G20 M7 G55\nX1\no100 endsub\n"
            "o200 sub\nM73\nM3 S2000\no100 call\nG1 X1\no200 endsub\n"
            "G10 L2 P2 X100\nG1 F100 X1\no200 call\nX2\no100 call")
    moves = interpret(text).moves
    events = [(m.name, m.line, m.origin) for m in moves if isinstance(m, Event)]
    # inside o200 (called from line 14): M3; o100's M7, its return (coolant off at its endsub,
    # line 5), o200's return (spindle off at line 11); o100 called from line 16: M7, and the
    # coolant off at its return, the program's last block
    assert events == [("spindle_cw", 8, 14), ("mist_on", 3, 14), ("coolant_off", 5, 14), ("spindle_off", 11, 14),
                      ("mist_on", 3, 16), ("coolant_off", 5, 16)]
    ends = [m.end for m in moves if isinstance(m, Line)]
    # o100 moves 1 inch in G91 under G55; o200's G1 X1 is back in G90, G54 (its caller's)
    assert ends == [(1, 0, 0), (26.4, 0, 0), (1, 0, 0), (2, 0, 0), (27.4, 0, 0)]


def test_m73_state_is_back_for_the_next_lines_expressions():
    """The restore happens at the return, before the language layer reads the next line: its
    expressions, assignments and conditions see the caller's units and coordinate system, and
    the persistent parameters are written in them (a reviewer's cases)."""
    program = interpret("G0 X10\no1 sub\nM73\nG20 G55\no1 endsub\no1 call\nG0 X[#5420 + 1]\n#<cs> = #5220\n"
                        "o2 if [#<cs> EQ 1]\nG0 Y1\no2 endif")
    assert [m.end for m in program.moves] == [(10, 0, 0), (11, 0, 0), (11, 1, 0)]
    assert interpret("o1 sub\nM73\nG20\n#5221 = 1\no1 endsub\no1 call").saved[5221] == pytest.approx(25.4)


def test_m72_restores_the_tool_length_status_not_its_value():
    """A tool-change subroutine with M73: G43 stays on, with the new tool's length (LinuxCNC
    keeps the status G43 / G43.1 / G49); a G49 saved comes back as G49; G43.1's values as
    they were."""
    tools = {1: {"length_mm": 10.0, "diameter_mm": 3.0}, 2: {"length_mm": 20.0, "diameter_mm": 6.0}}
    text = ("o<tc> sub\nM73\nG49\nT#1 M6\nG43 H#1\no<tc> endsub\nT1 M6 G43 H1\nG0 Z0\no<tc> call [2]\nG0 Z0\n"
            "M70\nG49\nM72\nG0 Z1\nG43.1 Z5\nM70\nG49\nM72\nG0 Z2\nG49\nM70\nG43 H1\nM72\nG0 Z3")
    ends = [m.end for m in interpret(text, tools=tools).moves if isinstance(m, Line)]
    assert ends == [(0, 0, 10), (0, 0, 20), (0, 0, 21), (0, 0, 7), (0, 0, 3)]


def test_m72_in_a_block_that_moves_under_the_g93_it_restores():
    program = interpret("G93\nG1 X1 F2\nM70\nG94 F100\nX2\nM72 X3 F4")
    assert program.moves[-1].feed == pytest.approx(4.0)     # 1 mm in 1/4 minute


@pytest.mark.parametrize("text,message", [
    ("M72", "line 1, column 1: M72: no modal state saved at this call level (M70 or M73 first)"),
    ("M70\nM71\nM72", "line 3, column 1: M72: no modal state saved at this call level (M70 or M73 first)"),
    ("o1 sub\nM72\no1 endsub\nM70\no1 call", "line 2, column 1: M72: no modal state saved at this call level "
                                            "(M70 or M73 first)"),
    ("M70 M72", "line 1, column 5: M72: two M codes of the modal state group in one block (M70 and M72)"),
])
def test_modal_state_refusals(text, message):
    with pytest.raises(GcodeError) as error:
        interpret(text)
    assert str(error.value) == message


def test_modal_state_refused_under_cutter_compensation():
    tools = {1: {"length_mm": 0.0, "diameter_mm": 2.0}}
    with pytest.raises(GcodeError) as error:
        interpret("G0 X-5 Y-5\nG41 D1 G1 X0 Y0 F600\nM70", tools=tools)
    assert str(error.value) == "line 3, column 1: M70: M70 cannot be used with cutter compensation on (G40 first)"
    with pytest.raises(GcodeError) as error:
        interpret("o1 sub\nM73\nG41 D1 G1 X0 Y0 F600\no1 endsub\nG0 X-5 Y-5\no1 call\nX10", tools=tools)
    assert str(error.value) == ("line 4, column 1: a subroutine with M73 returned with cutter compensation on: "
                                "its modal state cannot come back (G40 before the return)")


def test_g52_local_offset_shares_g92s():
    """G52 X Y Z: the words are the offset from the coordinate system's origin (LinuxCNC,
    Fanuc, Mach3), kept in G92's registers; axes not named keep theirs; G52 X0 Y0 Z0 ends it."""
    text = ("G10 L2 P1 X100\nG0 X0 Y0\nG52 X10 Y5\nG0 X0 Y0\nG52 X20\nG0 X0 Y0\nG92 X0\nG0 X1\n"
            "G52 X0 Y0 Z0\nG0 X0 Y0\nG20 G52 Z1\nG0 Z0")
    assert ends(text) == [(100, 0, 0), (110, 5, 0), (120, 5, 0), (121, 5, 0), (100, 0, 0),
                          (100, 0, pytest.approx(25.4))]
    program = interpret("G52 X2 Y3\nG0 X0 M2")
    assert program.saved[5210] == 1.0 and (program.saved[5211], program.saved[5212]) == (2.0, 3.0)
    with pytest.raises(GcodeError) as error:
        interpret("G52")
    assert str(error.value) == "line 1, column 1: G52: G52 needs at least one axis word"


def test_fanuc_home_idiom_g91_g28_z0():
    # G91 G28 Z0: the intermediate point is the current one, then Z alone goes home
    assert ends("G0 X5 Y5 Z-3\nG91 G28 Z0\nG90 G28 X0 Y0", g28=(1, 2, 3)) == [
        (5, 5, -3), (5, 5, 3), (0, 0, 3), (1, 2, 3)]


def test_g53_is_machine_coordinates_for_one_block():
    assert ends("G10 L2 P1 X100\nG0 X0\nG53 G0 X5\nG1 X1 F10") == [
        (100, 0, 0), (5, 0, 0), (101, 0, 0)]


def test_g28_g30_with_and_without_intermediate_point():
    text = "G0 X10 Y10 Z10\nG28\nG0 X1 Y1 Z1\nG28 Z5\nG30.1\nG0 X0 Y0 Z0\nG30 X2"
    assert ends(text, g28=(100, 200, 50)) == [
        (10, 10, 10), (100, 200, 50), (1, 1, 1), (1, 1, 5), (1, 1, 50), (0, 0, 0), (2, 0, 0),
        (1, 0, 0)]
    assert ends("G28.1\nG0 X1\nG28", g28=(9, 9, 9)) == [(1, 0, 0), (0, 0, 0)]


def test_parameters_are_updated_between_blocks():
    # #5420.. the position (work, program units), #5220 the system, #5221.. its offsets; a
    # block's words are evaluated before it runs, so in the units in force before it
    text = ("G10 L2 P2 X2\nG55 G20 G0 X1 Y2\nG21 G0 Y#5421\nG0 X#5420 Y[#5221 + #5241 + #5220]\n"
            "G92 Z1\nG0 Z[#5213]")
    assert ends(text) == [(2 + INCH, 2 * INCH, 0), (2 + INCH, 2, 0), (2 + INCH, 4, 0),
                          (2 + INCH, 4, -2)]


def test_program_assigns_an_offset_parameter():
    assert ends("#5221 = 7\nG54 G0 X1") == [(8, 0, 0)]


# ---- arcs ---------------------------------------------------------------------------------

def test_linuxcnc_centre_format_example():
    # the G2/G3 page's centre-format example: G0 X0 Y0 / G2 X1 Y1 I1 F10
    (arc,) = [m for m in moves("G0 X0 Y0\nG2 X1 Y1 I1 F10") if isinstance(m, Arc)]
    assert arc == Arc((0, 0, 0), (1, 1, 0), (1, 0, 0), "XY", False, 1, 10, 2)


def test_linuxcnc_g2_g3_pair_and_turns_examples():
    # the G2/G3 page: G2 X0 Y1 I1 J0.5 F25 / G3 X0 Y0 I1 J-0.5 F25 (centre (1, 0.5) both)
    ms = paths("G0 X0 Y0\nG2 X0 Y1 I1 J0.5 F25\nG3 X0 Y0 I1 J-0.5 F25")
    assert [(m.centre, m.ccw, m.end) for m in ms] == [
        ((1, 0.5, 0), False, (0, 1, 0)), ((1, 0.5, 0), True, (0, 0, 0))]
    # its multiple-turns example: G2 X0 Y1 Z-1 I1 J0.5 P2 F25, a helix of two turns
    (arc,) = paths("G0 X0 Y0 Z0\nG2 X0 Y1 Z-1 I1 J0.5 P2 F25")
    assert arc == Arc((0, 0, 0), (0, 1, -1), (1, 0.5, 0), "XY", False, 2, 25, 2)


def test_linuxcnc_helix_example_is_refused_as_linuxcnc_does():
    # the page's helix example G17 G2 X10 Y16 I3 J4 Z-1 from the origin: the radius to the
    # start is 5, to the end 13.89, far beyond the tolerance
    assert error("G0 X0 Y0 Z0\nG17 G2 X10 Y16 I3 J4 Z-1 F10") == (
        "line 2, column 16: I3: the radius to the end (13.8924) differs from the radius to the "
        "start (5.0000) by 8.892 mm, more than 0.5, or more than 0.005 and 0.1 %")
    (arc,) = paths("G0 X7 Y7 Z0\nG17 G2 X10 Y16 I3 J4 Z-1 F10")[1:]   # a start on its circle
    assert arc.end == (10, 16, -1) and arc.centre == (10, 11, 0)


def test_linuxcnc_radius_format_example():
    # the G2/G3 page's radius-format example: G17 G2 X10 Y15 R20 Z5 (from the origin)
    (arc,) = paths("G17 G2 X10 Y15 R20 Z5 F10")
    centre = arc.centre
    assert math.dist(centre[:2], (0, 0)) == pytest.approx(20)
    assert math.dist(centre[:2], (10, 15)) == pytest.approx(20)
    assert arc.end == (10, 15, 5) and centre[2] == 0          # helix: Z moves linearly
    # clockwise and less than half a turn: the centre lies to the right of the chord
    assert (10 * centre[1] - 15 * centre[0]) < 0


def test_negative_r_is_the_long_arc():
    (short,) = paths("G2 X10 R10 F10")
    (long,) = paths("G2 X10 R-10 F10")
    assert close(short.centre, (5, -math.sqrt(75), 0)) and close(long.centre, (5, math.sqrt(75), 0))


def test_full_circles_turns_and_helix():
    ms = paths("G0 X10\nG3 I-10 F100\nG2 X10 Y0 Z-3 I-10 P3")
    assert ms[1] == Arc((10, 0, 0), (10, 0, 0), (0, 0, 0), "XY", True, 1, 100, 2)
    assert ms[2].turns == 3 and ms[2].end == (10, 0, -3) and ms[2].centre == (0, 0, 0)
    assert error("G2 X1 I1 P0 F10") == (
        "line 1, column 10: P0: the number of turns must be a whole number 1 .. 10000")
    assert error("G2 X1 I1 P10001 F10").endswith("P10001: the number of turns must be a whole number 1 .. 10000")
    assert paths("G2 X0 Y0 I1 P10000 F10")[0].turns == 10000


def test_planes():
    # G18: u = Z, v = X, K and I the centre; G19: u = Y, v = Z, J and K
    (zx,) = paths("G18 G2 X10 Z10 K10 F10")
    assert zx.plane == "ZX" and zx.centre == (0, 0, 10) and not zx.ccw
    (yz,) = paths("G19 G3 Y10 Z10 J10 F10")
    assert yz.plane == "YZ" and yz.centre == (0, 10, 0) and yz.ccw
    assert error("G18 G2 X10 Z10 J10 K10 F10") == (
        "line 1, column 16: J10: J is not an offset of the G18 plane")
    assert paths("G17 G2 X10 I5 K0 F10")[0].end == (10, 0, 0)      # K0: FreeCAD's habit


def test_g18_direction_follows_the_right_hand_rule_about_y():
    # G3 (counter-clockwise seen from +Y) from Z=+1 turns towards X=+1: quarter arc to (1, 0, 0)
    (arc,) = paths("G0 Z1\nG18 G3 X1 Z0 R1 F10")[1:]
    assert close(arc.centre, (0, 0, 0)) and arc.ccw


def test_absolute_arc_centres():
    (arc,) = paths("G10 L2 P1 X100\nG0 X0\nG90.1 G2 X10 I5 J0 F10")[1:]
    assert arc.centre == (105, 0, 0)
    assert error("G90.1 G2 X10 I5 F10") == (
        "line 1, column 7: G2: G90.1 (absolute centre) needs both I and J")


def test_radius_tolerance():
    # accepted: radii differ by 0.004 mm (< 0.005 mm); by 0.02 mm on a radius of 100 (0.02 %)
    assert len(paths("G2 X10.004 I5 F10")) == 1
    assert len(paths("G2 X200.02 I100 F10")) == 1
    assert error("G2 X10.01 I5 F10") == (
        "line 1, column 11: I5: the radius to the end (5.0100) differs from the radius to the "
        "start (5.0000) by 0.01 mm, more than 0.5, or more than 0.005 and 0.1 %")
    assert error("G2 X200.6 I100 F10").endswith("by 0.6 mm, more than 0.5, or more than 0.005 "
                                                 "and 0.1 %")
    assert error("G20 G2 X1.001 I.5 F10").startswith("line 1, column 15: I.5: the radius")


@pytest.mark.parametrize("text,message", [
    ("G2 X1 I0 F10", "line 1, column 7: I0: zero-radius arc (radius 0.0000 at the start, "
                     "1.0000 at the end)"),
    ("G2 R5 F10", "line 1, column 4: R5: an R arc needs an end point different from its start"),
    ("G2 X10 R4 F10", "line 1, column 8: R4: the radius is too small to reach the end point "
                      "(half the chord is 5.0000)"),
    ("G2 X10 I5 R5 F10", "line 1, column 8: I5: an arc takes either R or I/J/K, not both"),
    ("G2 X10 F10", "line 1, column 1: G2: an arc in the G17 plane needs I or J (the centre) "
                   "or R"),
    ("G2 X10 I5", "line 1, column 1: G2: feed move without a feed rate (no F word yet)"),
])
def test_bad_arcs(text, message):
    assert error(text) == message


def test_arc_endpoint_error_within_tolerance_is_kept_for_the_compiler():
    (arc,) = paths("G2 X10.003 I5 F10")
    assert arc.end == (10.003, 0, 0) and arc.centre == (5, 0, 0)


# ---- canned cycles ------------------------------------------------------------------------

def cycle_steps(text):
    out = []
    for m in moves(text):
        if isinstance(m, Line):
            out.append(("G0" if m.feed is None else "G1", tuple(round(c, 6) for c in m.end)))
        elif isinstance(m, Dwell):
            out.append(("G4", m.seconds))
    return out


def test_g81_g98_and_g99():
    assert cycle_steps("G0 X0 Y0 Z10\nG98 G81 X5 Y5 Z-2 R1 F100\nX6")[1:] == [
        ("G0", (5, 5, 10)), ("G0", (5, 5, 1)), ("G1", (5, 5, -2)), ("G0", (5, 5, 10)),
        ("G0", (6, 5, 10)), ("G0", (6, 5, 1)), ("G1", (6, 5, -2)), ("G0", (6, 5, 10))]
    assert cycle_steps("G0 X0 Y0 Z10\nG99 G81 X5 Y5 Z-2 R1 F100\nX6")[1:] == [
        ("G0", (5, 5, 10)), ("G0", (5, 5, 1)), ("G1", (5, 5, -2)), ("G0", (5, 5, 1)),
        ("G0", (6, 5, 1)), ("G1", (6, 5, -2)), ("G0", (6, 5, 1))]


def test_cycle_below_r_rises_first():
    assert cycle_steps("G0 Z-1\nG81 X5 Z-3 R2 F100")[1:] == [
        ("G0", (0, 0, 2)), ("G0", (5, 0, 2)), ("G1", (5, 0, -3)), ("G0", (5, 0, 2))]


def test_g82_g85_g89():
    assert cycle_steps("G0 Z5\nG82 Z-1 R1 P0.5 F10 X1")[1:] == [
        ("G0", (1, 0, 5)), ("G0", (1, 0, 1)), ("G1", (1, 0, -1)), ("G4", 0.5), ("G0", (1, 0, 1))]
    assert cycle_steps("G0 Z5\nG98 G85 Z-1 R1 F10 X1")[-3:] == [
        ("G1", (1, 0, -1)), ("G1", (1, 0, 1)), ("G0", (1, 0, 5))]
    assert cycle_steps("G0 Z5\nG98 G89 Z-1 R1 P2 F10 X1")[-3:] == [
        ("G1", (1, 0, -1)), ("G4", 2), ("G1", (1, 0, 5))]


def test_g86_stops_the_spindle_in_the_hole():
    """G86: feed down, dwell, spindle off, rapid out, the spindle on again the way it turned
    (M4 here, at its S); without the spindle turning it is an error."""
    moves = interpret("G0 Z5\nM4 S800\nG98 G86 X1 Z-1 R1 P0.5 F10\nG80\n").moves
    assert [(type(m).__name__, getattr(m, "name", None)) for m in moves[-5:]] == [
        ("Line", None), ("Dwell", None), ("Event", "spindle_off"), ("Line", None), ("Event", "spindle_ccw")]
    assert moves[-1].value == 800 and moves[-2].end == (1, 0, 5) and moves[-4].seconds == 0.5
    assert "line 1, column 1: G86: G86 needs the spindle turning (M3 or M4)" in error("G86 X1 Z-1 R1 P1 F10")
    assert "needs a P word" in error("M3 S100\nG86 X1 Z-1 R1 F10")


def test_g83_and_g73_pecks():
    assert cycle_steps("G0 Z5\nG83 X1 Z-2 R1 Q1.5 F10")[3:] == [
        ("G1", (1, 0, -0.5)), ("G0", (1, 0, 1)), ("G0", (1, 0, -0.246)),
        ("G1", (1, 0, -2)), ("G0", (1, 0, 1))]
    assert cycle_steps("G0 Z5\nG73 X1 Z-2 R1 Q1.5 F10")[3:] == [
        ("G1", (1, 0, -0.5)), ("G0", (1, 0, -0.246)), ("G1", (1, 0, -2)), ("G0", (1, 0, 1))]
    # inch: the clearance is 0.010 inch
    assert cycle_steps("G20 G0 Z1\nG73 Z-.2 R.1 Q.2 F10")[3] == ("G0", (0, 0, -0.1 * INCH + 0.254))


def test_incremental_repeats_and_sticky_words():
    steps = cycle_steps("G0 X1 Z5\nG91 G99 G81 X2 Z-3 R-4 L3 F10")
    holes = [s[1] for s in steps if s[0] == "G1"]
    assert holes == [(3, 0, -2), (5, 0, -2), (7, 0, -2)]      # R 5-4 = 1, bottom 1-3 = -2
    holes = [s[1] for s in cycle_steps("G0 Z5\nG81 X1 Z-1 R1 F10\nX2\nY3") if s[0] == "G1"]
    assert holes == [(1, 0, -1), (2, 0, -1), (2, 3, -1)]


def test_cycle_in_g19_plane_drills_along_x():
    steps = cycle_steps("G0 X5\nG19 G98 G81 Y1 Z2 X-1 R1 F10")[1:]
    assert steps == [("G0", (5, 1, 2)), ("G0", (1, 1, 2)), ("G1", (-1, 1, 2)), ("G0", (5, 1, 2))]


def test_polar_bolt_circle_of_the_linuxcnc_sample():
    text = "G20 G17 G90\nG0 X1.5 Y0 Z0\nG91 G81 R.1 Z-.5 ^60 L6 F10\nM2"
    holes = [s[1] for s in cycle_steps(text) if s[0] == "G1"]
    assert len(holes) == 6
    for n, (x, y, z) in enumerate(holes, 1):
        assert close((x, y), (1.5 * INCH * math.cos(math.radians(60 * n)),
                              1.5 * INCH * math.sin(math.radians(60 * n))), 1e-6)
        assert z == pytest.approx(-0.4 * INCH)


@pytest.mark.parametrize("text,message", [
    ("G81 X1 Z-1 F10", "line 1, column 1: G81: canned cycle without an R word (the retract "
                       "plane)"),
    ("G81 X1 R1 F10", "line 1, column 1: G81: canned cycle without a Z word (the bottom of the "
                      "hole)"),
    ("G83 X1 Z-1 R1 F10", "line 1, column 1: G83: needs a Q word (the peck depth)"),
    ("G82 X1 Z-1 R1 F10", "line 1, column 1: G82: needs a P word (the dwell in seconds)"),
    ("G81 X1 Z2 R1 F10", "line 1, column 1: G81: the R plane is below the bottom of the hole (Z)"),
    ("G81 X1 Z-1 R1 L0 F10", "line 1, column 15: L0: the number of repeats L must be a whole "
                             "number >= 1"),
    ("G93 G81 X1 Z-1 R1 F10", "line 1, column 5: G81: canned cycles cannot be used in inverse "
                              "time mode (G93)"),
    ("G81 X1 Z-1 R1", "line 1, column 1: G81: canned cycle without a feed rate (no F word yet)"),
    ("G91 G81 X1 Z-1 R1 L500000 F10", "line 1, column 19: L500000: this canned cycle would make "
                                      "more than 1000000 moves (500000 holes of 1 pecks)"),
    ("G83 X1 Z-100 R1 Q0.0001 F10", "line 1, column 17: Q0.0001: this canned cycle would make "
                                    "more than 1000000 moves (1 holes of 1010000 pecks)"),
])
def test_bad_cycles(text, message):
    assert error(text) == message


# ---- dwell, path modes, tools -------------------------------------------------------------

def test_dwell_and_path_modes():
    program = interpret("G4 P1.5\nG1 X1 F600\nG61 X2\nG64 P0.01 Q0.02 X3\nX4\nG20 G64 P0.001 X0\nG61.1 X1\n"
                        "G64 X2")
    assert program.moves[0] == Dwell(1.5, 1)
    assert [m.path_control for m in program.moves[1:]] == \
        [("G64", None), ("G61", None), ("G64", 0.01), ("G64", 0.01), ("G64", pytest.approx(0.0254)),
         ("G61.1", None), ("G64", None)]


def test_path_modes_in_run_order():
    # a subroutine's G61 holds for the moves made after it runs, not for those before its
    # call (nor a loop's G64 P for the turns before it changes it)
    text = "o100 sub\nG61\no100 endsub\nG1 X1 F600\no100 call\nX2\nX3"
    assert [m.path_control for m in interpret(text).moves] == [("G64", None), ("G61", None), ("G61", None)]
    text = "#1=0\no1 while [#1 LT 2]\nG1 X[#1+1] F600\nG64 P0.1\n#1=[#1+1]\no1 endwhile"
    assert [m.path_control for m in interpret(text).moves] == [("G64", None), ("G64", 0.1)]


@pytest.mark.parametrize("code", ["G61", "G61.1", "G64 P0.1"])
def test_path_control_refused_under_cutter_compensation(code):
    # LinuxCNC refuses it too: the compensated move is made a block late, under the new mode
    tools = {1: {"length_mm": 0.0, "diameter_mm": 2.0}}
    with pytest.raises(GcodeError) as error:
        interpret(f"G0 X-5 Y-5\nG41 D1 G1 X0 Y0 F600\n{code}\nX10", tools=tools)
    word = code.split()[0]
    assert str(error.value) == (f"line 3, column 1: {word}: the path-control mode cannot change with cutter "
                                "compensation on (G40 first)")
    program = interpret(f"G0 X-5 Y-5\nG41 D1 G1 X0 Y0 F600\nX10\nG40 {code} G0 X20", tools=tools)
    assert program.moves[-1].path_control[0] == word


def test_tool_length_offsets():
    tools = {1: {"length_mm": 10.0, "diameter_mm": 3.0}, 2: {"length_mm": 20.0, "diameter_mm": 6}}
    text = "T1 M6\nG43 G0 Z0\nG43 H2 Z0\nG49 Z0\nG43.1 Z5\nG0 Z0\nG49"
    assert ends(text, tools=tools) == [(0, 0, 10), (0, 0, 20), (0, 0, 0), (0, 0, 5)]
    program = interpret("T3 M6\nG43 G0 Z1", tools=tools)
    assert program.warnings == ["line 2: G43: tool 3 is not in the tool table; its length is "
                                "taken as 0"]
    assert tools[1]["length_mm"] == 10.0                       # the caller's table is not changed


def test_g10_tool_table():
    assert ends("G10 L1 P4 Z12.5 R1\nT4 M6 G43 G0 Z0") == [(0, 0, 12.5)]
    assert ends("G0 Z30\nG10 L10 P4 Z10\nT4 M6 G43 G0 Z10") == [(0, 0, 30)]
    assert ends("G0 Z30\nG10 L10 P4 Z10\nT4 M6 G43\nG0 Z0") == [(0, 0, 30), (0, 0, 20)]


# ---- events -------------------------------------------------------------------------------

def events(text, **kw):
    return [(m.name, m.value, m.line) for m in moves(text, **kw) if isinstance(m, Event)]


def test_spindle_select_zero():
    """LinuxCNC's $ spindle select (M3 $0 S1, its plasma samples): spindle 0 is this machine's."""
    assert events("M3 $0 S100\nM5 $0") == [("spindle_cw", 100, 1), ("spindle_off", 0, 2)]
    assert error("M3 $1 S100") == "line 1, column 4: $1: this machine has one spindle, $0"


def test_spindle_coolant_outputs_and_stops():
    text = ("S1000 M3\nS1200\nS1200\nM4 S500\nM5\nS10\nM7 M8\nM9\nM62 P1\nM65 P2\nT3\nM6\n"
            "M0\nM1\nM60\nM30\nG0 X100\nM3")
    assert events(text) == [
        ("spindle_cw", 1000, 1), ("spindle_speed", 1200, 2), ("spindle_ccw", 500, 4),
        ("spindle_off", 0, 5), ("mist_on", 0, 7), ("flood_on", 0, 7), ("coolant_off", 0, 8),
        ("output_on", 1, 9), ("output_off", 2, 10), ("tool_change", 3, 12), ("pause", 6, 12),
        ("pause", 0, 13), ("pause", 1, 14), ("pause", 60, 15), ("program_end", 30, 16)]
    assert all(name in EVENTS for name, _, _ in events(text))
    assert paths(text) == []                                   # nothing after M30 runs


def test_tool_selected_in_the_block_of_m6():
    assert events("M6 T2") == [("tool_change", 2, 1), ("pause", 6, 1)]


def test_home_parameters_assigned_by_the_program():
    assert ends("#5161 = 5\n#5183 = -1\nG28\nG30", g30=(7, 8, 9)) == [(5, 0, 0), (7, 8, -1)]


def test_stop_comes_after_the_motion_of_its_block():
    ms = moves("G1 X1 F10 M2")
    assert isinstance(ms[0], Line) and ms[1] == Event("program_end", 2, 1)


def test_overrides_are_ignored_with_a_warning_and_messages_are_collected():
    program = interpret("M48\n(MSG, hello there)\nM50 P0")
    assert program.warnings == ["line 1: M48: overrides are not modelled; ignored",
                                "line 3: M50: overrides are not modelled; ignored"]
    assert program.messages == ["line 2: hello there"]
    # a message reaches a terminal: control characters escaped, other text kept
    program = interpret("(MSG, clear\x1b[2J\x07 Привет)")
    assert program.messages == ["line 1: clear\\x1b[2J\\x07 Привет"]


def test_debug_print_and_abort_comments():
    """LinuxCNC's (DEBUG, ...) and (PRINT, ...): messages with #N and #<name> as printf's %lf
    (|v| < 0.0001 as 0), "######" for an undefined name; DEBUG only while #5599 > 0 (1 at the
    start).  (ABORT, ...) ends the program with its text as the error of its line."""
    program = interpret("#1=2.5\n#<d>=-1\n(debug, a #1 d #<D> e #< d > x #<nope> #2 # y)\n(PRINT,#3)\n"
                        "#5599=0\n(debug, hidden)\n(print, shown #1)\n#5599=1\n(Debug,0.00001 is #4)\n#4=0.00001")
    assert program.messages == ["line 3: a 2.500000 d -1.000000 e -1.000000 x ###### 0.000000 # y",
                                "line 4: 0.000000", "line 7: shown 2.500000", "line 9: 0.00001 is 0.000000"]
    assert interpret("#4=0.00001\n(debug,#4)\n(debug,#5)\n#5=-0.00002").messages == \
        ["line 2: 0.000000", "line 3: 0.000000"]
    assert error("G1 X1 F100\no1 if [#5070 EQ 0]\n(ABORT, probe failed: #5070)\no1 endif\nG1 X2") == \
        "line 3, column 1: (ABORT) probe failed: 0.000000"
    assert interpret("(MSG, plain #1)\n(abortive comment)\n(MSG , spaced)\n( msg,lead)").messages == \
        ["line 1: plain #1", "line 4: lead"]                   # (LinuxCNC: "msg," at the start)
    with pytest.raises(GcodeError) as caught:                  # the messages before the abort go with it
        interpret("(MSG, one)\n(debug, two)\n(abort)\n(abort,)\n")
    assert str(caught.value) == "line 4, column 1: (ABORT)" and caught.value.messages == ["line 1: one", "line 2: two"]
    program = interpret("G38.2 Z-5 F100\n(abort, #5063)")              # after a touch taken at the move's end
    assert program.warnings[-1] == ("line 2: (ABORT) -5.000000: not taken, since a probe move before it took "
                                    "its touch at the end of the move")


def test_move_limit(monkeypatch):
    # the moves of a program, an arc's turns counted, are at most MAX_MOVES: loops of many-turn
    # arcs stop within seconds
    import interp.gcode.interpreter as interpreter
    monkeypatch.setattr(interpreter, "MAX_MOVES", 1000)
    assert error("F100\nG2 X0 I1 P600\nG2 X0 I1 P600") == \
        "line 3, column 1: the program makes more than 1000 moves (an arc's turns counted): split it"
    assert error("F100\no1 repeat [600]\nG1 X1\nG1 X0\no1 endrepeat").startswith("line 3, column 1: the program")


def test_an_endless_loop_with_moves_stops_within_seconds():
    start = time.perf_counter()
    assert error("F100\no1 while [1]\nG1 X1\nG1 X0\no1 endwhile").endswith(
        "o1 endwhile: more than 100000 loop iterations: a loop that never ends?")
    assert time.perf_counter() - start < 30


def test_unused_axes_at_zero_are_accepted():
    assert ends("G0 X1 A0 B0 C0\nG91 G0 U0 X1\nG92 A5") == [(1, 0, 0), (2, 0, 0)]


def test_block_delete_lines_are_skipped():
    assert ends("G0 X1\n/G0 X5\nG0 Y1") == [(1, 0, 0), (1, 1, 0)]


# ---- random programs against an independent model ----------------------------------------

_VALUES = st.integers(-400, 400).map(lambda n: n / 8)


def _random_program(draw_ops):
    lines = ["G10 L2 P2 X3 Y-7 Z1.5"]
    machine = [0.0, 0.0, 0.0]
    offsets = {1: [0.0, 0.0, 0.0], 2: [3.0, -7.0, 1.5]}
    system, g92, scale, absolute = 1, [0.0, 0.0, 0.0], 1.0, True

    def offset(a):
        return offsets[system][a] + g92[a]

    for op, args in draw_ops:
        if op == "units":
            scale = INCH if args else 1.0
            lines.append("G20" if args else "G21")
        elif op == "distance":
            absolute = args
            lines.append("G90" if args else "G91")
        elif op == "system":
            system = args
            lines.append("G54" if args == 1 else "G55")
        elif op == "g92":
            g92 = [machine[a] - offsets[system][a] - args[a] * scale for a in range(3)]
            lines.append("G92 X%s Y%s Z%s" % args)
        elif op in ("G0", "G1"):
            for a, v in enumerate(args):
                machine[a] = v * scale + offset(a) if absolute else machine[a] + v * scale
            lines.append("%s X%s Y%s Z%s F100" % ((op,) + args))
        elif op == "helix":                   # full circle with a Z move
            dz, i = args
            machine[2] = dz * scale + offset(2) if absolute else machine[2] + dz * scale
            lines.append(f"G3 Z{dz} I{i} J0 F100")
        elif op == "rarc":                    # incremental R arc
            dx, dy = args
            radius = math.hypot(dx, dy) / 2 + 1
            machine[0] += dx * scale
            machine[1] += dy * scale
            lines.append(f"G91 G2 X{dx} Y{dy} R{radius} F100")
            if absolute:
                lines.append("G90")
    work = tuple((machine[a] - offset(a)) / scale for a in range(3))
    return "\n".join(lines), tuple(machine), work, "inch" if scale != 1.0 else "mm"


_OPS = st.lists(st.one_of(
    st.tuples(st.just("units"), st.booleans()),
    st.tuples(st.just("distance"), st.booleans()),
    st.tuples(st.just("system"), st.sampled_from([1, 2])),
    st.tuples(st.just("g92"), st.tuples(_VALUES, _VALUES, _VALUES)),
    st.tuples(st.sampled_from(["G0", "G1"]), st.tuples(_VALUES, _VALUES, _VALUES)),
    st.tuples(st.just("helix"), st.tuples(_VALUES, st.integers(1, 40))),
    st.tuples(st.just("rarc"), st.tuples(_VALUES, _VALUES).filter(lambda d: d != (0, 0))),
), max_size=25)


@settings(max_examples=150, deadline=None)
@given(_OPS)
def test_random_programs_end_where_the_model_says(ops):
    text, machine, work, units = _random_program(ops)
    program = interpret(text)
    assert close(program.end_machine, machine, 1e-6), text
    assert close(program.end_work, work, 1e-6), text
    assert program.units == units
    assert continuous(program), text


def test_random_programs_seeded():
    seed = random.randrange(2**32)
    print("seed", seed)
    rng = random.Random(seed)
    for _ in range(20):
        ops = []
        for _ in range(rng.randrange(1, 30)):
            v = tuple(rng.randrange(-400, 400) / 8 for _ in range(3))
            ops.append(rng.choice([("units", rng.random() < 0.5), ("distance", rng.random() < 0.5),
                                   ("system", rng.choice([1, 2])), ("g92", v), ("G1", v),
                                   ("rarc", (v[0] or 1, v[1]))]))
        text, machine, work, _ = _random_program(ops)
        program = interpret(text)
        assert close(program.end_machine, machine, 1e-6), (seed, text)
        assert continuous(program), (seed, text)


# ---- the public corpus --------------------------------------------------------------------

CORPUS = Path(os.environ.get("INTERP_GCODE_CORPUS", ROOT.parent / "shared" / "gcode"))
# programs refused for a genuine reason: the word the one-line error names
REFUSED = {
    "cura_own_gcode.gcode": "",                 # 3D printer (Marlin): M140, E axis, G5 ...
    "lcnc_metric_wrench.ngc": "F#<_hal[plasmac.cut-feed-rate]>",  # feed from a HAL pin
    "lcnc_comp.ngc": "d1",                      # G42 D1: tool 1 is not in the tool table
    "ur5_drawing.gcode": "M300",                # pen-plotter servo M300 (not RS274NGC)
}
CORPUS_FILES = sorted(p.name for p in CORPUS.glob("*") if p.suffix != ".md") \
    if CORPUS.is_dir() else []


@pytest.mark.skipif(not CORPUS.is_dir(), reason=f"no G-code corpus at {CORPUS}")
@pytest.mark.parametrize("name", CORPUS_FILES)
def test_corpus_program(name):
    text = (CORPUS / name).read_bytes().decode("utf-8", errors="surrogateescape")
    if name in REFUSED:
        with pytest.raises(GcodeError) as info:
            interpret(text)
        assert f": {REFUSED[name]}: " in str(info.value) or not REFUSED[name]
        return
    program = interpret(text, tools={1: {"length_mm": 0.0, "diameter_mm": 3.0}})
    assert continuous(program)
    assert any(isinstance(m, (Line, Arc)) for m in program.moves)
    for move in program.moves:
        if isinstance(move, Line) and move.feed is not None or isinstance(move, Arc):
            assert move.feed > 0


# ---------------- subroutine files ----------------

def test_subroutine_files_from_folders(tmp_path):
    """o<name> call finds name.ngc in the first folder that has it; its moves carry the
    program's line of the call, and an error the interpreter finds in it names the file and
    its line, after the call's line."""
    first, second = tmp_path / "a", tmp_path / "b"
    first.mkdir(), second.mkdir()
    (first / "drill.ngc").write_text("o<drill> sub\nG0 X#1\nG1 Z-1 F100\nG0 Z0\no<drill> endsub\n")
    (second / "drill.ngc").write_text("o<drill> sub\nG0 Y#1\no<drill> endsub\n")
    (second / "arc.ngc").write_text("o<arc> sub\nG1 X1 F100\nG2 X3 R0.1\no<arc> endsub\n")
    program = interpret("G21 G90\no<drill> call [5]\nG0 X0\n", folders=[first, second])
    assert [(m.line, m.end) for m in program.moves] == [(2, (5.0, 0.0, 0.0)), (2, (5.0, 0.0, -1.0)),
                                                        (2, (5.0, 0.0, 0.0)), (3, (0.0, 0.0, 0.0))]
    assert interpret("G21 G90\no<drill> call [5]\n", folders=[second]).moves[0].end == (0.0, 5.0, 0.0)
    with pytest.raises(GcodeError) as info:
        interpret("G21 G90\n\no<arc> call\n", folders=[first, second])
    assert str(info.value) == (f"line 3: {second / 'arc.ngc'}: line 3, column 7: R0.1: the radius is too small to "
                               "reach the end point (half the chord is 1.0000)")
    with pytest.raises(GcodeError, match="no arc.ngc in the subroutine folders"):
        interpret("o<arc> call\n", folders=[first])
