"""Small helpers shared by the benchmarks (timing, throw-away venvs and databases, log-log fits, tables)."""

from __future__ import annotations

import contextlib
import math
import os
import subprocess
import sys
import time
import venv
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit, urlunsplit

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))


def best_of(fn: Callable[[], Any], repeats: int) -> tuple[Any, float]:
    """(last result, best wall time in seconds over ``repeats`` runs)."""
    best, out = math.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - start)
    return out, best


def ensure_venv(path: Path, requirement: str | Sequence[str], module: str) -> Path:
    """A virtual environment at ``path`` with ``requirement`` (one or several) installed (kept for later runs);
    its python."""
    python = path / "bin" / "python"
    if python.exists() and subprocess.run([python, "-c", f"import {module}"], capture_output=True).returncode == 0:
        return python
    wanted = [requirement] if isinstance(requirement, str) else list(requirement)
    print(f"installing {' '.join(wanted)} into {path} ...", flush=True)
    venv.EnvBuilder(with_pip=True, clear=True).create(path)
    subprocess.run([python, "-m", "pip", "install", "-q", *wanted], check=True)
    return python


def loadavg() -> str:
    """The 1, 5 and 15 minute load averages as printed by uptime ("n/a" where /proc is missing)."""
    try:
        return " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        return "n/a"


def fit_exponent(xs: Sequence[float], ys: Sequence[float]) -> float:
    """Least-squares slope of log(y) against log(x): the growth exponent k in y ~ x^k."""
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly, strict=True)) / sum((a - mx) ** 2 for a in lx)


def table(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    cells = [[f"{c:.4g}" if isinstance(c, float) else str(c) for c in row] for row in rows]
    widths = [max(len(h), *(len(r[i]) for r in cells)) for i, h in enumerate(headers)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(headers, widths, strict=True))]
    lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in cells]
    return "\n".join(lines)


def recreate_database(url: str) -> str:
    """Drop (closing its connections) and create the PostgreSQL database of ``url``; returns ``url``."""
    import psycopg

    parts = urlsplit(url)
    name = parts.path.lstrip("/")
    with psycopg.connect(urlunsplit(parts._replace(path="/postgres")), autocommit=True) as conn:
        conn.execute(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)')
        conn.execute(f'CREATE DATABASE "{name}"')
    return url


def drop_database(url: str) -> None:
    """Drop the PostgreSQL database of ``url``, closing its connections."""
    import psycopg

    parts = urlsplit(url)
    with psycopg.connect(urlunsplit(parts._replace(path="/postgres")), autocommit=True) as conn:
        conn.execute(f'DROP DATABASE IF EXISTS "{parts.path.lstrip("/")}" WITH (FORCE)')


@contextlib.contextmanager
def throwaway_database(suffix: str) -> Iterator[str]:
    """A fresh PostgreSQL database named after ``$DATABASE_URL``'s plus ``suffix``, made the process's
    ``DATABASE_URL`` (Django settings not yet loaded) and dropped at the end; yields its URL."""
    base = os.environ.get("DATABASE_URL", "postgres://postgres@127.0.0.1:5432/continuum")
    parts = urlsplit(base)
    url = recreate_database(urlunsplit(parts._replace(path=f"/{parts.path.lstrip('/')}{suffix}")))
    os.environ["DATABASE_URL"] = url
    os.environ.setdefault("DJANGO_SETTINGS_MODULE", "continuum.settings")
    try:
        yield url
    finally:
        from django.db import connections

        connections.close_all()
        drop_database(url)


def print_top(stats: Any, title: str, orders: Sequence[str] = ("cumulative", "tottime"), n: int = 25) -> None:
    """Print the ``n`` top rows of a ``pstats.Stats`` for each sort order, under ``title`` (which the order ends)."""
    import io

    for order in orders:
        out = io.StringIO()
        stats.stream = out
        stats.sort_stats(order).print_stats(n)
        lines = [line for line in out.getvalue().splitlines() if line.strip()]
        start = next((i for i, line in enumerate(lines) if "ncalls" in line), 0)
        print(f"\n{title}, top {n} by {order}:")
        print("\n".join(lines[start : start + n + 1]))
