# SPDX-License-Identifier: Apache-2.0
"""Point 7: the merged correction equals points 5 + 6 (+ 8) for every E, L, S, L', S'."""
from hypothesis import given, strategies as st

from interp.models.curve import literal_update, merged_update

mag = st.integers(0, 1 << 30)


@given(e=st.integers(-(1 << 33), 1 << 33), l=mag, s=mag, l2=mag, s2=mag, switch=st.booleans())
def test_merged_equals_points_5_6_8(e, l, s, l2, s2, switch):
    assert merged_update(e, l, s, l2, s2, switch, improved=False) == literal_update(e, l, s, l2, s2, switch)


def test_merged_differs_from_improved():
    """The check is not vacuous: the improved formula is a different one."""
    assert merged_update(-5, 10, 3, 11, 4, False, improved=False) != merged_update(-5, 10, 3, 11, 4, False, improved=True)
