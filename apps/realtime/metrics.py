"""The RT scheduler's Prometheus metrics, under kube-scheduler's names where they mean the same (``continuum_``
prefix, ``profile="RT-scheduler"``), so a kube-scheduler dashboard's queries work with the prefix changed:

- ``continuum_scheduler_scheduling_attempt_duration_seconds{result, profile}``: per pod, the time of the
  attempt that decided it (a cycle decides every pending pod at once: each pod observes its cycle's decide
  time); ``result`` is ``scheduled`` or ``unschedulable`` as in kube-scheduler (a failed cycle counts in
  ``continuum_scheduler_cycle_errors_total``).
- ``continuum_scheduler_schedule_attempts_total{result, profile}``: the same attempts, counted.
- ``continuum_scheduler_framework_extension_point_duration_seconds{extension_point="Bind", status, profile}``:
  each Binding's round trip (kube-scheduler's bind duration since 1.23; ``status`` ``Success`` or ``Error``).
- ``continuum_scheduler_pending_pods{queue}``: pods waiting for this scheduler at the last cycle: ``active``
  (being decided) and ``unschedulable`` (decided: no node fits).
"""

from __future__ import annotations

from prometheus_client import Counter, Gauge, Histogram

from continuum.metrics import DURATION_BUCKETS, PREFIX

PROFILE = "RT-scheduler"

ATTEMPT_SECONDS = Histogram(
    f"{PREFIX}_scheduler_scheduling_attempt_duration_seconds",
    "Scheduling attempt latency in seconds (decide step of the cycle that decided the pod)",
    ["result", "profile"],
    buckets=DURATION_BUCKETS,
)
ATTEMPTS = Counter(
    f"{PREFIX}_scheduler_schedule_attempts", "Number of attempts to schedule pods, by the result", ["result", "profile"]
)
EXTENSION_SECONDS = Histogram(
    f"{PREFIX}_scheduler_framework_extension_point_duration_seconds",
    "Latency for running a specific extension point (here: Bind, the Binding's round trip)",
    ["extension_point", "status", "profile"],
    buckets=DURATION_BUCKETS,
)
PENDING = Gauge(f"{PREFIX}_scheduler_pending_pods", "Pending pods, by the queue they are in", ["queue"])


def attempted(seconds: float, scheduled: int, unschedulable: int) -> None:
    """One cycle decided ``scheduled + unschedulable`` pods in ``seconds``."""
    for result, count in (("scheduled", scheduled), ("unschedulable", unschedulable)):
        if count:
            ATTEMPTS.labels(result, PROFILE).inc(count)
            histogram = ATTEMPT_SECONDS.labels(result, PROFILE)
            for _ in range(count):
                histogram.observe(seconds)
    PENDING.labels("active").set(0)
    PENDING.labels("unschedulable").set(unschedulable)


def waiting(pods: int) -> None:
    """Pods waiting for this scheduler when a cycle starts deciding."""
    PENDING.labels("active").set(pods)
    if not pods:
        PENDING.labels("unschedulable").set(0)


CYCLE_ERRORS = Counter(f"{PREFIX}_scheduler_cycle_errors", "RT scheduler cycles that failed (retried with back-off)")


def cycle_failed() -> None:
    CYCLE_ERRORS.inc()


def bound(seconds: float, ok: bool) -> None:
    EXTENSION_SECONDS.labels("Bind", "Success" if ok else "Error", PROFILE).observe(seconds)
