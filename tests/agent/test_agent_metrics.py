"""The node agent's /metrics (--metrics-port): overruns, reports sent and kernel rejections, parsed by
prometheus_client's parser while the agent runs a real SCHED_DEADLINE command."""

from __future__ import annotations

import signal
import subprocess
import sys

from continuum.agent.metrics import PREFIX, AgentCollector
from continuum.agent.report import Reporter
from tests.agent.test_agent import HOG, PATIENT, PYTHON, ROOT, deadline_capable  # noqa: F401
from tests.kubeapi import free_port
from tests.scrape import parse, scrape_until, total


def test_a_hogs_overruns_and_reports_are_scraped_while_it_runs(server):
    server["realtime"]("hogm", period=10, deadline=10, wcet=2)
    port = free_port()
    cmd = [sys.executable, "-m", "continuum.agent", "run", "--realtime", "hogm", "--server", server["url"],
           "--allow-http", "--token", server["token"], "--node", "node0", *PATIENT,
           "--metrics-port", str(port), "--metrics-linger", "1", "--", PYTHON, "-c", HOG.format(s=600)]  # fmt: skip
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        families = scrape_until(
            f"http://127.0.0.1:{port}/metrics",
            lambda f: total(f, f"{PREFIX}_overruns_total") > 0 and total(f, f"{PREFIX}_reports_sent_total") > 1,
            timeout=240,
            what="overruns counted and reports acknowledged",
        )
        assert total(families, f"{PREFIX}_overruns_total", node="node0", container="hogm") > 0
        assert total(families, f"{PREFIX}_kernel_rejections_total") == 0
    finally:
        proc.send_signal(signal.SIGTERM)  # forwarded to the hog; the agent lingers 1 s and ends
        try:
            proc.wait(60)
        except subprocess.TimeoutExpired:
            proc.kill()
        proc.communicate()


def test_a_kernel_rejection_is_exposed():
    reporter = Reporter(None)
    collector = AgentCollector(reporter, "node0", "heavy")
    collector.rejected = True
    reporter.kernel_rejected("the kernel's admission control refused the reservation (EBUSY)")
    from prometheus_client import CollectorRegistry, generate_latest

    registry = CollectorRegistry()
    registry.register(collector)
    families = parse(generate_latest(registry).decode())
    assert total(families, f"{PREFIX}_kernel_rejections_total", node="node0", container="heavy") == 1
    assert total(families, f"{PREFIX}_overruns_total") == 0
