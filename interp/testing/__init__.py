# SPDX-License-Identifier: Apache-2.0
"""Test support shared by the cocotb benches in tb/: the cycle-by-cycle scoreboard (tbkit.py)
and the checks every motion core gets (corecheck.py)."""
