# SPDX-License-Identifier: Apache-2.0
"""The host side of the UART link to the board controller (docs/host-driver.md):
frames (protocol), command records (records), the sender (driver), a Python model
of the controller's frame layer for tests (devicemodel)."""
