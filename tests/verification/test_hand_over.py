"""Applying an allocation to running handlers: the one hand-over rule shared by the elected coordinator and
the server (``apply_allocation``). A late handler keeps its monitors (a second copy would duplicate verdicts);
only a gone one's monitors start afresh; a migration in flight is left to finish."""

import time
import uuid

import pytest

from apps.verification.models import AllocationRun
from apps.verification.services import apply_allocation
from continuum.verification_runtime.bus import Bus
from continuum.verification_runtime.coordinator import gone_handlers, hand_over

from .test_runtime import REDIS_URL, _redis_or_fail

pytestmark = pytest.mark.services


@pytest.fixture
def bus():
    _redis_or_fail()
    bus = Bus(REDIS_URL, prefix=f"cvhand{uuid.uuid4().hex[:8]}")
    yield bus
    bus.clear()


def _report(bus: Bus, ages: dict[str, float]) -> None:
    for name, age in ages.items():
        bus.report(name, {"wall": time.time() - age, "free_cpu": 50})


def _sent(bus: Bus, handler: str) -> list[tuple[str, dict]]:
    return [(kind, body) for _, kind, body in bus.requests(handler, "0-0")]


def test_late_handler_keeps_its_monitor_gone_handler_loses_it(bus):
    _report(bus, {"a": 0, "b": 0, "late": 5, "gone": 60})
    for monitor, host in {"m_live": "a", "m_late": "late", "m_gone": "gone"}.items():
        bus.set_allocation(monitor, host)
    live, gone = {"a", "b"}, gone_handlers(bus.handlers(), dead_after=10)
    assert gone == {"gone"}
    acted = hand_over(bus, {"m_live": "b", "m_late": "b", "m_gone": "b", "m_new": "a"}, live, gone)
    assert sorted(acted) == ["m_gone", "m_live", "m_new"]
    assert _sent(bus, "a") == [("MIGRATE", {"monitor": "m_live", "to": "b"}), ("EXEC", {"monitors": ["m_new"]})]
    assert _sent(bus, "b") == [("EXEC", {"monitors": ["m_gone"]})]
    assert _sent(bus, "late") == []
    assert bus.allocation() == {"m_live": "b", "m_late": "late", "m_gone": "b", "m_new": "a"}
    assert bus.moving() == {"m_live": {"source": "a", "target": "b"}}


def test_migration_in_flight_is_left_alone_unless_an_end_is_gone(bus):
    _report(bus, {"a": 0, "b": 0, "c": 0, "gone": 60})
    bus.set_allocation("m1", "a")
    bus.set_allocation("m2", "a")
    bus.start_moving("m1", "a", "b")  # under way
    bus.start_moving("m2", "a", "gone")  # its target died: it will never finish
    acted = hand_over(bus, {"m1": "c", "m2": "c"}, {"a", "b", "c"}, {"gone"})
    assert acted == ["m2"]
    assert _sent(bus, "a") == [("MIGRATE", {"monitor": "m2", "to": "c"})]
    assert bus.moving() == {"m1": {"source": "a", "target": "b"}, "m2": {"source": "a", "target": "c"}}


def test_target_not_live_gets_nothing(bus):
    _report(bus, {"a": 0, "late": 5})
    assert hand_over(bus, {"m": "late"}, {"a"}, set()) == []
    assert _sent(bus, "late") == [] and bus.allocation() == {}


@pytest.mark.django_db
def test_server_applies_a_stored_run_with_the_same_rule(settings, cluster):
    _redis_or_fail()
    settings.CONTINUUM_VERIFICATION_REDIS_URL = REDIS_URL
    settings.CONTINUUM_VERIFICATION_PREFIX = f"cvapply{uuid.uuid4().hex[:8]}"
    settings.CONTINUUM_HANDLER_LIVENESS_S = 3
    settings.CONTINUUM_HANDLER_GONE_AFTER_S = 10
    bus = Bus(REDIS_URL, prefix=f"{settings.CONTINUUM_VERIFICATION_PREFIX}:{cluster.pk}")
    try:
        _report(bus, {"node0": 5, "node1": 0})  # node0 is late (5 s), not gone (10 s)
        bus.set_allocation("m1", "node0")
        run = AllocationRun.objects.create(fleet=cluster.fleet, cluster=cluster, result={"allocation": {"m1": "node1"}})
        apply_allocation(run, cluster)
        assert _sent(bus, "node1") == [] and _sent(bus, "node0") == []  # before: a second copy on node1
        assert bus.allocation() == {"m1": "node0"}
        _report(bus, {"node0": 60})  # now gone
        apply_allocation(run, cluster)
        assert _sent(bus, "node1") == [("EXEC", {"monitors": ["m1"]})]
        run.refresh_from_db()
        assert run.applied and bus.allocation() == {"m1": "node1"}
    finally:
        bus.clear()
