# SPDX-License-Identifier: Apache-2.0
"""FPGA flows: synthesis and place-and-route (synth.py), SymbiYosys proofs (formal.py),
FuseSoC core files (fusesoc.py)."""
