# SPDX-License-Identifier: Apache-2.0
"""Simulation: the cocotb runner (runner.py), the cocotb drivers behind `interp run` / `interp gcode` /
`interp curve-error`, the native speed harness, and the files a run writes."""
