"""What an RT scheduler cycle reads from the database (see :mod:`apps.realtime.scheduler`): the cluster row, its
RT policy, its node rows, when its next monitor taint expires, and the monitor's active node taints.

A cycle run on its own reads them inline. While the scheduler loops, an rt-taints thread reads them ahead: the
taints each time the pod watch reports a new pending pod (a database round trip of 2-30 ms on a loaded machine,
done while the loop wakes and prepares the cycle, not after), and the rest before it is due (two queries, see
``CycleState._read_state``): a deciding cycle holds no database read.
"""

from __future__ import annotations

import logging
import threading
import time

from django.db import close_old_connections, connection
from django.db.models import Min, Q
from django.utils import timezone

from apps.clusters.models import Cluster, ComputeNode

from .kube import problem
from .models import NodeTaint, RTPolicy

log = logging.getLogger("continuum.rt_scheduler")

#: Seconds a cycle waits for the rt-taints thread's read of the monitor's taints before reading them itself.
TAINT_WAIT = 1.0
#: The rt-taints thread reads the cycle's state (see CycleState.get) once it is this fraction of a period old.
STATE_AHEAD = 0.9

#: The cluster, its RT policy and its node rows by name.
State = tuple[Cluster, RTPolicy, dict[str, ComputeNode]]
#: A monitor taint's row: (node name, key, value, effect, expires_at).
TaintRow = tuple


class CycleState:
    """One cluster's cycle state; ``period``: the scheduler's (the state is at most that old while it loops)."""

    def __init__(self, cluster_id: int, period: float) -> None:
        self.cluster_id = cluster_id
        self.period = period
        #: Monotonic time the next monitor taint expires (None: no taint), as of the last read of the state.
        self.expiry_at: float | None = None
        self._state: State | None = None
        self._state_at = 0.0
        #: The taints read ahead: the thread reads them when asked (a new pending pod, a cycle); (monotonic time
        #: the newest read started, its rows or None: failed). ``_ahead``: the thread runs.
        self._cond = threading.Condition()
        self._asked = 0.0
        self._taints: tuple[float, list[TaintRow] | None] | None = None
        self._ahead = False

    # ---- the cluster, its policy, its node rows --------------------------------------------------------------
    def get(self, fresh: bool = False) -> State:
        """The state: read now when ``fresh`` or unless the thread runs, else at most a period old (a change of
        the policy or of a node's RT attributes applies within that; a taint is lifted when it expires)."""
        if fresh or self._state is None or not self._ahead or time.monotonic() - self._state_at >= self.period:
            self._read_state()
        assert self._state is not None
        return self._state

    def _read_state(self) -> None:
        """Two queries: the cluster with its policy and its next taint expiry, then its nodes (it was four, 7-19 ms
        of CPU per period under eviction churn)."""
        now = time.monotonic()
        cluster = (
            Cluster.objects.select_related("rt_policy")
            .annotate(next_expiry=Min("rt_taints__expires_at", filter=Q(rt_taints__lifted_at__isnull=True)))
            .get(pk=self.cluster_id)
        )
        try:
            policy = cluster.rt_policy
        except RTPolicy.DoesNotExist:
            policy = RTPolicy.for_cluster(cluster)
        rows = {n.name: n for n in cluster.nodes.all()}
        expiry = cluster.next_expiry
        self._state = (cluster, policy, rows)
        self.expiry_at = None if expiry is None else now + max(0.0, expiry.timestamp() - time.time())
        self._state_at = now

    # ---- the monitor's active taints ---------------------------------------------------------------------------
    def read_taints(self) -> list[TaintRow]:
        """The monitor's active taints, read now."""
        return list(
            NodeTaint.objects.filter(
                cluster_id=self.cluster_id, lifted_at__isnull=True, expires_at__gt=timezone.now()
            ).values_list("node__name", "key", "value", "effect", "expires_at")
        )

    def ask_taints(self, since: float) -> None:
        """A read of the taints starting after ``since`` (monotonic) is wanted (the thread does it)."""
        with self._cond:
            if since > self._asked:
                self._asked = since
                self._cond.notify_all()

    def active_taints(self, need: float) -> list[TaintRow]:
        """The taint rows of a read that started after ``need`` (monotonic: when the newest pending pod of the
        cycle was seen) and less than a period ago: the thread's, else read here."""
        floor = max(need, time.monotonic() - self.period)
        if self._ahead:
            with self._cond:
                got = self._taints
                if got is None or got[0] < floor:
                    if floor > self._asked:
                        self._asked = floor
                        self._cond.notify_all()
                    self._cond.wait_for(lambda: not self._ahead or self._read_since(floor), TAINT_WAIT)
                    got = self._taints
            if got is not None and got[0] >= floor and got[1] is not None:
                return got[1]
        return self.read_taints()

    def _read_since(self, floor: float) -> bool:
        return self._taints is not None and self._taints[0] >= floor

    # ---- the rt-taints thread ------------------------------------------------------------------------------------
    def start(self, stop: threading.Event) -> threading.Thread:
        """Read ahead in a thread until ``stop`` is set or :meth:`stop` is called."""
        self._ahead = True
        thread = threading.Thread(target=self._loop, args=(stop,), daemon=True, name="rt-taints")
        thread.start()
        return thread

    def stop(self) -> None:
        """Inline reads from now on; the thread ends."""
        self._ahead = False
        with self._cond:
            self._cond.notify_all()

    def _loop(self, stop: threading.Event) -> None:
        """Reads the taints each time a read newer than the last is asked for, and the state before a cycle
        would have to."""
        last = 0.0
        try:
            while not stop.is_set() and self._ahead:
                with self._cond:
                    while self._asked < last and not stop.is_set() and self._ahead:
                        left = self._state_at + STATE_AHEAD * self.period - time.monotonic()
                        if left <= 0:
                            break
                        self._cond.wait(left)
                    if stop.is_set() or not self._ahead:
                        break
                if time.monotonic() - self._state_at >= STATE_AHEAD * self.period:
                    try:
                        self._read_state()
                    except Exception as exc:  # the loop reads it itself when it is due (and fails there)
                        log.info("RT scheduler: reading the cluster's state failed (%s)", problem(exc))
                        close_old_connections()
                        stop.wait(self.period)
                    if self._asked < last:
                        continue
                started = time.monotonic()
                rows: list[TaintRow] | None
                try:
                    rows = self.read_taints()
                except Exception as exc:  # the cycle reads them itself (and fails there if the database is down)
                    log.info("RT scheduler: reading the monitor's taints failed (%s)", problem(exc))
                    close_old_connections()
                    rows = None
                last = started
                with self._cond:
                    self._taints = (started, rows)
                    self._cond.notify_all()
        finally:
            connection.close()
