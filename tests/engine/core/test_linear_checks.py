"""Duplicate and membership checks are linear in their input (issue 25: ``names.count(n)`` per name held a web
thread for a minute on one 919 KiB placement request). Counted in comparisons, not timed: a name type that counts
its ``==`` calls makes a quadratic check show n^2 comparisons on any machine."""

from __future__ import annotations

import pytest

from continuum.engine.containers.superclustering import ContainerSpec, Workload
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform, Processor
from continuum.engine.core.unique import duplicates, first_duplicate
from continuum.engine.verification.stl_monitor import parse_trace_csv

N = 3000


class Counted(str):
    """A str that counts how often it is compared for equality."""

    calls = 0

    def __eq__(self, other: object) -> bool:
        Counted.calls += 1
        return str.__eq__(self, other)

    __hash__ = str.__hash__


@pytest.fixture(autouse=True)
def _reset():
    Counted.calls = 0


def test_duplicates_are_found_in_order_of_their_second_occurrence():
    assert duplicates(["a", "b", "a", "c", "b", "a"]) == ["a", "b"]
    assert first_duplicate(["x", "y", "y", "x"]) == "y"
    assert first_duplicate([]) is None and duplicates([]) == []


def test_a_workload_checks_its_container_names_in_linear_comparisons():
    Workload([ContainerSpec(name=Counted(f"c{i}")) for i in range(N)])
    assert Counted.calls <= 4 * N  # quadratic: N^2 = 9,000,000
    with pytest.raises(InputError, match="duplicate container name 'c1'"):
        Workload([ContainerSpec(name=n) for n in ("c0", "c1", "c2", "c1")])


def test_a_platform_checks_its_processor_ids_in_linear_comparisons():
    Platform([Processor(id=Counted(f"p{i}")) for i in range(N)])
    assert Counted.calls <= 4 * N
    with pytest.raises(InputError, match="duplicate processor id 'p1'"):
        Platform([Processor(id=i) for i in ("p0", "p1", "p1")])


def test_a_trace_header_names_its_first_repeated_column():
    with pytest.raises(InputError, match="column 's1' appears twice"):
        parse_trace_csv("time,s1,s2,s1\n0,1,2,3\n")
    with pytest.raises(InputError, match="an empty column name"):
        parse_trace_csv("time,,s2\n0,1,2\n")
