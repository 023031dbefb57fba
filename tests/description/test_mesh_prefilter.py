"""The mesh magnitude scan's prefilter (robokit.description.mesh_size._maybe_huge) says "maybe" exactly
where one regular expression for both of its conditions finds a match — 13 digits in a row, or an
exponent of 12 or more — on random bytes biased toward number-like text (hypothesis), and on the
edges: runs of 12 and 13 digits at the start, the end and across the whole input."""
import re

from hypothesis import given, settings
from hypothesis import strategies as st

from robokit.description.mesh_size import _largest_number, _maybe_huge

ONE_PATTERN = re.compile(rb"[0-9]{13}|[eE]\+?0*(?:[0-9]{3}|1[2-9]|[2-9][0-9])")

_pieces = st.sampled_from([b"0", b"1", b"9", b"12", b"e", b"E", b"+", b"-", b".", b" ", b"\n", b"e12", b"e+0013",
                           b"1234567890", b"00", b"x", b"\xff", b"<p>"])


@settings(max_examples=400, deadline=None)
@given(st.lists(_pieces, max_size=40).map(b"".join))
def test_the_prefilter_is_the_single_expression(raw):
    assert _maybe_huge(raw) == (ONE_PATTERN.search(raw) is not None)


def test_runs_of_digits_at_the_edges():
    for k in (12, 13, 14):
        for raw in (b"7" * k, b"7" * k + b" 1", b"1 " + b"7" * k, b"a" + b"7" * k + b"a"):
            assert _maybe_huge(raw) == (k >= 13) == (ONE_PATTERN.search(raw) is not None), raw


def test_a_huge_number_in_a_text_mesh_is_still_found():
    assert _largest_number(b"v 0 0 0\nv 1 0 0\nv 0 1 12345678901234\n", "obj") == 12345678901234.0
    assert _largest_number(b"v 0 0 0\nv 1e13 0 0\n", "obj") == 1e13
    assert _largest_number(b"v 0 0 0\nv 1.5e-13 0 0\n", "obj") == 0.0


def test_runs_across_the_blocks_counted_apart_are_found():
    from robokit.description import mesh_size

    n = mesh_size._BLOCK
    for at in (n - 13, n - 12, n - 7, n - 1, n, 2 * n - 6):
        raw = bytearray(b" " * (2 * n + 40))
        for k, digits in ((13, True), (12, False)):
            raw[:] = b" " * len(raw)
            raw[at:at + k] = b"7" * k
            assert _maybe_huge(bytes(raw)) is digits, (at, k)
