"""Prometheus metrics of every Continuum process (issue 28): where they are served from, nothing Django.

Each long-running process defines its own metrics next to the code that counts them (``continuum_`` prefix;
kube-scheduler's names where a metric means the same) in the process's default registry, and serves them:

- the web app at ``/metrics`` (:mod:`continuum.web_metrics`: only with ``CONTINUUM_METRICS_TOKEN`` set, only to
  ``Authorization: Bearer <token>``);
- a Celery worker, the cluster agent and the RT scheduler on their own port (:func:`serve_from_env`:
  ``CONTINUUM_METRICS_PORT``, bound to ``CONTINUUM_METRICS_ADDR``, default loopback: in a pod the manifests
  set ``0.0.0.0`` and a NetworkPolicy admits only the scraper);
- the node agent with ``--metrics-port`` (:mod:`continuum.agent.metrics`).

Processes that fork workers (gunicorn, Celery's prefork pool) count in their children: with
``PROMETHEUS_MULTIPROC_DIR`` set (an empty directory, before the process starts) every child writes its
values there and the scrape sums them (prometheus_client's multiprocess mode; :func:`registry`).
"""

from __future__ import annotations

import logging
import os
from typing import Any

from prometheus_client import REGISTRY, CollectorRegistry, multiprocess, start_http_server

log = logging.getLogger(__name__)

PREFIX = "continuum"
#: Seconds buckets for durations from a cache read (ms) to a slow API round trip (s); kube-scheduler's are
#: exponential from 1 ms too.
DURATION_BUCKETS = (0.001, 0.002, 0.004, 0.008, 0.016, 0.032, 0.064, 0.128, 0.256, 0.512, 1.024, 2.048, 4.096,
                    8.192, 16.384)  # fmt: skip


def multiprocess_dir() -> str | None:
    return os.environ.get("PROMETHEUS_MULTIPROC_DIR") or None


def registry() -> CollectorRegistry:
    """What a scrape reads: the process's registry, or every child's values in multiprocess mode."""
    if multiprocess_dir():
        merged = CollectorRegistry()
        multiprocess.MultiProcessCollector(merged)
        return merged
    return REGISTRY


def port_from_env(default: int | None = None) -> int | None:
    """``CONTINUUM_METRICS_PORT`` as a port (0: any free one), ``default`` when unset; ValueError names it."""
    text = os.environ.get("CONTINUUM_METRICS_PORT", "").strip()
    if not text:
        return default
    if not text.isdigit() or int(text) > 65535:
        raise ValueError(f"CONTINUUM_METRICS_PORT must be a port number (0-65535), not {text!r}")
    return int(text)


def serve(port: int, addr: str | None = None) -> tuple[Any, int]:
    """Serve ``/metrics`` on ``addr:port`` from a daemon thread; returns the server and the port it bound."""
    addr = addr or os.environ.get("CONTINUUM_METRICS_ADDR") or "127.0.0.1"
    server, _thread = start_http_server(port, addr=addr, registry=registry())
    bound = server.server_port
    log.info("metrics on http://%s:%d/metrics", addr, bound)
    return server, bound


def serve_from_env(what: str) -> int | None:
    """Serve when ``CONTINUUM_METRICS_PORT`` is set; the port bound (logged as ``{what} metrics on ...``)."""
    port = port_from_env()
    if port is None:
        return None
    _server, bound = serve(port)
    log.warning("%s: metrics on port %d", what, bound)
    return bound
