# SPDX-License-Identifier: Apache-2.0
"""Host side of the UART link to the controller: frames, records, the sender, the register map."""
