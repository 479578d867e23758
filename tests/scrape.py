"""Scraping a ``/metrics`` endpoint and reading it with prometheus_client's own parser (the format check)."""

from __future__ import annotations

import time
import urllib.error
import urllib.request
from collections.abc import Callable

from prometheus_client.parser import text_string_to_metric_families


def parse(text: str) -> dict[str, dict[tuple, float]]:
    """{family name: {(sample name, sorted labels...): value}}; raises if the text is not valid exposition."""
    families: dict[str, dict[tuple, float]] = {}
    for family in text_string_to_metric_families(text):
        samples = families.setdefault(family.name, {})
        for s in family.samples:
            samples[(s.name, *sorted(s.labels.items()))] = s.value
    return families


def scrape(url: str, headers: dict[str, str] | None = None, timeout: float = 30) -> dict[str, dict[tuple, float]]:
    request = urllib.request.Request(url, headers=headers or {})
    with urllib.request.urlopen(request, timeout=timeout) as response:
        assert response.headers["Content-Type"].startswith("text/plain")
        return parse(response.read().decode())


def total(families: dict[str, dict[tuple, float]], sample: str, **labels: str) -> float:
    """The sum of the samples named ``sample`` whose labels include ``labels``."""
    family = families.get(sample.removesuffix("_total").removesuffix("_count").removesuffix("_sum"), {})
    return sum(
        v for (name, *pairs), v in family.items() if name == sample and all((k, w) in pairs for k, w in labels.items())
    )


def scrape_until(
    url: str, condition: Callable[[dict], bool], timeout: float = 120, what: str = "the metrics"
) -> dict[str, dict[tuple, float]]:
    """Scrape until ``condition(families)`` holds (a bound for a stuck test, not a speed)."""
    end = time.monotonic() + timeout
    last: object = None
    while time.monotonic() < end:
        try:
            families = scrape(url, timeout=10)
        except (OSError, urllib.error.URLError) as exc:
            last = exc
        else:
            if condition(families):
                return families
            last = {k: v for k, v in families.items() if k.startswith("continuum")}
        time.sleep(0.2)
    raise AssertionError(f"{what} not seen at {url} within {timeout} s; last: {last}")
