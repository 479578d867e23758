"""Bounded concurrency for pushes (issue 15): a push's API calls overlap, at most N at a time.

A push is many independent create (+ bind) calls, each a round trip to the API server; done one after the
other, the push waits for the network and the server's etcd write of every pod in turn. Here they run in a
pool of ``CONTINUUM_KUBE_PUSH_CONCURRENCY`` = N threads (:func:`concurrency`), started in the caller's order
(the pool's queue is FIFO: when item i starts, every earlier item has started and all but at most N - 1 of them
have finished; so pods are created in decreasing rank order, spec 02 §7.3, up to a window of N; strictly with
N = 1), with the results returned in that order. Bounded, so a push of 10,000 pods never
opens 10,000 connections to the server nor floods its admission (the server's max-in-flight limits).

Work runs in the pool's threads; ``progress`` is called in the caller's thread as each item finishes (it may
write to the database: a job's progress row, whose connection belongs to the caller's thread). When an item
raises one of ``fatal`` (the API went away, or its retries ran out), the push stops: items not started yet
are answered ``skipped(reason)``, items in flight finish, and the first such reason is returned.
"""

from __future__ import annotations

import queue
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any, TypeVar

from django.conf import settings

T = TypeVar("T")
R = TypeVar("R")

#: Upper bound of the setting: beyond this a push only queues at the server (its default max-in-flight is 400
#: mutating requests for *all* clients) and holds as many connections open.
MAX_CONCURRENCY = 64


def concurrency() -> int:
    """API calls a push has in flight at most: ``CONTINUUM_KUBE_PUSH_CONCURRENCY`` within 1..64."""
    return max(1, min(int(settings.CONTINUUM_KUBE_PUSH_CONCURRENCY), MAX_CONCURRENCY))


def run_bounded(
    items: Sequence[T],
    work: Callable[[T], R],
    *,
    skipped: Callable[[str], R],
    fatal: tuple[type[BaseException], ...],
    describe: Callable[[BaseException], str],
    workers: int | None = None,
    progress: Callable[[int], None] | None = None,
) -> tuple[list[R], str | None]:
    """``[work(item) for item in items]`` with at most ``workers`` (default :func:`concurrency`) running at once;
    returns the results in ``items``' order and the reason the run stopped early (``None``: it did not).

    An exception that is not one of ``fatal`` is a bug: it propagates (the items not started are cancelled)."""
    workers = workers or concurrency()
    stop = threading.Event()
    reason: list[str] = []
    lock = threading.Lock()

    def one(item: T) -> R:
        if stop.is_set():
            return skipped(reason[0])
        try:
            return work(item)
        except fatal as exc:
            with lock:
                if not reason:
                    reason.append(describe(exc))
            stop.set()
            return skipped(reason[0])

    results: list[R | None] = [None] * len(items)
    if not items:
        return [], None
    # Each finished item reports its index on a queue: the caller's thread waits on one queue, not on every
    # pending future (concurrent.futures.wait registers a waiter on each: quadratic in the items, which a push
    # of thousands of pods pays in CPU its threads need).
    finished: queue.SimpleQueue[tuple[int, BaseException | None]] = queue.SimpleQueue()

    def tracked(i: int, item: T) -> None:
        try:
            results[i] = one(item)
        except BaseException as exc:  # a bug: handed to the caller's thread, which raises it
            finished.put((i, exc))
            return
        finished.put((i, None))

    with ThreadPoolExecutor(max_workers=min(workers, len(items)), thread_name_prefix="kube-push") as pool:
        futures = [pool.submit(tracked, i, item) for i, item in enumerate(items)]
        for done_count in range(1, len(items) + 1):
            _, error = finished.get()
            if error is not None:
                for future in futures:
                    future.cancel()
                raise error
            if progress is not None:
                progress(done_count)
    return results, (reason[0] if reason else None)  # type: ignore[return-value]


def gather(*calls: Callable[[], Any]) -> list[Any]:
    """Run independent calls at once (a push's reads before its first write: three round trips in the time of
    one); their results in order. The first call's exception, in the given order, is raised after all ended."""
    with ThreadPoolExecutor(max_workers=max(1, len(calls)), thread_name_prefix="kube-gather") as pool:
        futures = [pool.submit(fn) for fn in calls]
    return [f.result() for f in futures]
