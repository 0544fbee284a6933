# SPDX-License-Identifier: Apache-2.0
"""interp/benchmarks/link.py: the queue model (pure Python, no simulator)."""
import pytest

from interp.benchmarks.link import capacity, ceiling, queue_low


def test_ceiling_and_capacity():
    # 3 Mbaud: 300 000 characters/s, 128 of every 134 are payload, 68 bytes a record
    assert ceiling(3_000_000, 68) == pytest.approx(300_000 * 128 / 134 / 68)
    assert capacity(68) == 4096 // 68 + 8 == 68


def test_fast_link_keeps_the_queue_full():
    times = [0.01 * (k + 1) for k in range(500)]           # a command every 10 ms
    low, waits = queue_low(times, 1000.0, 10)               # a record every 1 ms
    assert waits == 0 and low == 9                          # refilled before the next start


def test_slow_link_starves():
    times = [0.01 * (k + 1) for k in range(500)]
    low, waits = queue_low(times, 50.0, 10)                 # a record every 20 ms: half the pace
    assert low == 0 and waits > 200


def test_hand_computed():
    # 3 slots, commands of 1 s; records every 0.4 s once a slot frees: record 3 comes at
    # max(0 + 0.4, end of command 0 = 1.0) = 1.0, just in time; record 4 at max(1.4, 2.0)
    low, waits = queue_low([1.0, 2.0, 3.0, 4.0, 5.0, 6.0], 2.5, 3)
    assert (low, waits) == (2, 0)
    # the first record of the stream only: one slot, the next comes 2 s after the first
    low, waits = queue_low([1.0, 2.0, 3.0], 0.5, 1)
    assert waits == 2 and low == 0
