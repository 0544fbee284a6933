# SPDX-License-Identifier: Apache-2.0
"""Plots (matplotlib, no display needed): stepped paths over the programmed path (paths.py)."""
