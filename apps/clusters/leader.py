"""Leader election of a cluster's component (the cluster agent, the RT scheduler) on a Lease in the cluster's
own namespace (the one Continuum owns there): :mod:`apps.kube.leader` with the cluster's credentials."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from apps.kube.leader import LeaderElector, LeaseLock, Timing, identity

from .kube import api_client_for
from .models import Cluster


def elector(cluster: Cluster, name: str, namespace: str | None = None, timing: Timing | None = None,
            holder: str | None = None) -> LeaderElector:  # fmt: skip
    lock = LeaseLock(lambda: api_client_for(cluster), namespace or cluster.namespace, name, holder or identity())
    return LeaderElector(lock, timing)


def elected(
    cluster: Cluster,
    name: str,
    work: Callable[[threading.Event], Any],
    stop: threading.Event,
    namespace: str | None = None,
    timing: Timing | None = None,
) -> None:
    """Run ``work(lost)`` whenever this process holds the Lease ``name`` of ``cluster``, until ``stop``."""
    elector(cluster, name, namespace, timing).run(work, stop)
