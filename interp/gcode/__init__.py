# SPDX-License-Identifier: Apache-2.0
"""The G-code front end: language (lark grammar), RS274NGC interpreter, machine file, compiler."""
