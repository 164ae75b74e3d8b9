"""The quota core: which kept files go, oldest first, to fit the quota; never a protected one."""

from __future__ import annotations

import pytest

from servodesk.storage.quota import MB, Kept, describe_bytes, over_quota

A, B, C = Kept("a", 40 * MB, 1.0), Kept("b", 30 * MB, 2.0), Kept("c", 50 * MB, 3.0)


@pytest.mark.parametrize(
    ("items", "keep", "protect", "doomed"),
    [
        ([A, B, C], 200 * MB, (), []),  # fits
        ([A, B, C], 120 * MB, (), []),  # exactly the quota
        ([A, B, C], 100 * MB, (), ["a"]),  # the oldest goes first
        ([C, B, A], 60 * MB, (), ["a", "b"]),  # by age, not by the order given
        ([A, B, C], 60 * MB, ("a",), ["b", "c"]),  # a protected one is stepped over
        ([A, B, C], 10 * MB, ("c",), ["a", "b"]),  # the protected one stays even when alone over
        ([], 0, (), []),
    ],
)
def test_the_oldest_go_until_the_rest_fits(
    items: list[Kept], keep: int, protect: tuple[str, ...], doomed: list[str]
) -> None:
    assert over_quota(items, keep, protect) == doomed


@pytest.mark.parametrize(
    ("size", "text"),
    [(0, "0 B"), (1023, "1023 B"), (1536, "1.5 kB"), (3 * MB, "3.0 MB"), (5 << 40, "5120.0 GB")],
)
def test_sizes_in_words(size: int, text: str) -> None:
    assert describe_bytes(size) == text
