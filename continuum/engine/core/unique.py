"""Duplicates in a list in linear time.

Every "is a name listed twice" check goes through here: ``[n for n in names if names.count(n) > 1]`` is
quadratic, and one 919 KiB placement request held a web thread for a minute with it (issue 25).
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable
from typing import TypeVar

__all__ = ["duplicates", "first_duplicate"]

T = TypeVar("T", bound=Hashable)


def duplicates(items: Iterable[T]) -> list[T]:
    """The items that occur more than once, each once, in the order their second occurrence is met."""
    seen: set[T] = set()
    again: dict[T, None] = {}
    for item in items:
        if item in seen:
            again[item] = None
        else:
            seen.add(item)
    return list(again)


def first_duplicate(items: Iterable[T]) -> T | None:
    """The first item met a second time, None when all are distinct."""
    seen: set[T] = set()
    for item in items:
        if item in seen:
            return item
        seen.add(item)
    return None
