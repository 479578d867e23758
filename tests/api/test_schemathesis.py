"""Schemathesis against the whole REST API, in process, on whichever database the run uses.

The OpenAPI document is loaded from the app itself (``/api/schema/``, authenticated with a fleet token),
then schemathesis' own engine (what ``schemathesis run`` executes) drives the WSGI application directly:
the examples phase (with examples generated where the schema has none), the fuzzing phase and the stateful
phase (sequences of calls along the links it infers from the schema), bounded per operation. The check is
``not_a_server_error``: no generated request, valid or not, may make the server answer 5xx or raise.

A fleet, a cluster (with nodes and links) and an application exist beforehand, so that list, detail and
action endpoints see real rows. Two edits are made to every generated request, both for the test machine's
sake and not to hide anything: ``kubeconfig`` is removed (a cluster with a Kubernetes API would make
``sync``/``push`` connect to whatever address the generator wrote) and the thesis case-study simulation is
kept short (jobs run inside the request here, with no broker, and its bounds allow minutes of work).

scripts/test runs this file a second time on SQLite (``DATABASE_URL=sqlite:///...``), so both databases
the project supports are exercised. Environment variables (the defaults keep one run to a few minutes on
two cores):

- ``CONTINUUM_SCHEMATHESIS_EXAMPLES`` (15): generated cases per operation in the fuzzing phase;
- ``CONTINUUM_SCHEMATHESIS_SCENARIOS`` (50) and ``CONTINUUM_SCHEMATHESIS_STEPS`` (6): stateful sequences;
- ``CONTINUUM_SCHEMATHESIS_COVERAGE=1``: also the coverage phase (boundary values, ~13,000 more cases);
- ``CONTINUUM_SCHEMATHESIS_CHECKS=response_schema_conformance,...``: more checks.
"""

from __future__ import annotations

import os
import threading
from collections import Counter
from dataclasses import dataclass, field

import pytest
import schemathesis
from schemathesis.engine import events as st_events
from schemathesis.engine import from_schema

pytestmark = pytest.mark.django_db(transaction=True)

MAX_EXAMPLES = int(os.environ.get("CONTINUUM_SCHEMATHESIS_EXAMPLES", "15"))
MAX_STEPS = int(os.environ.get("CONTINUUM_SCHEMATHESIS_STEPS", "6"))
MAX_SCENARIOS = int(os.environ.get("CONTINUUM_SCHEMATHESIS_SCENARIOS", "50"))  # stateful call sequences
# the coverage phase (boundary values of every parameter) adds many cases: off by default for CI time
COVERAGE = os.environ.get("CONTINUUM_SCHEMATHESIS_COVERAGE", "") not in ("", "0")
# more schemathesis checks to run besides not_a_server_error, e.g. "response_schema_conformance"
EXTRA_CHECKS = [c for c in os.environ.get("CONTINUUM_SCHEMATHESIS_CHECKS", "").split(",") if c]

STATS: Counter = Counter()  # what the hooks saw, for the run's report
_LOCK = threading.Lock()


@schemathesis.hook
def before_call(context, case, kwargs):
    if isinstance(case.body, dict) and "kubeconfig" in case.body:
        # never a cluster with a Kubernetes API: sync/push would connect to a generated address
        case.body = {k: v for k, v in case.body.items() if k != "kubeconfig"}
    if case.operation.path == "/api/v1/allocations/simulate/" and case.method == "POST":
        # one simulated second, not minutes of MILP solves inside one request (no body: the defaults' 120 s)
        if not isinstance(case.body, (dict, list, str, bytes, int, float)):
            case.body = {}
        if not isinstance(case.body, dict):
            return
        body = dict(case.body)
        for name, most in (("duration_s", 1), ("time_limit", 0.05)):
            value = body.get(name, most)  # absent: the case study's own length, minutes of solving
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                body[name] = min(value, most)
        case.body = body


@schemathesis.hook
def after_call(context, case, response):
    from django.db import connections

    with _LOCK:
        STATS[f"responses {response.status_code // 100}xx"] += 1
    if threading.current_thread() is not threading.main_thread():
        # the in-process WSGI client never closes the response, so Django's request_finished (which closes
        # the request's connection) does not fire: close the worker thread's connection here, or the test
        # database could not be dropped at the end
        connections.close_all()


@dataclass
class Run:
    cases: Counter = field(default_factory=Counter)  # phase -> cases executed
    failures: dict = field(default_factory=dict)  # (operation, failure title) -> (message, reproduction)
    errors: list = field(default_factory=list)
    transitions: str = ""


def _run(schema) -> Run:
    run = Run()
    for event in from_schema(schema).execute():
        if isinstance(event, st_events.PhaseStarted) and event.payload is not None:
            p = event.payload
            run.transitions = f"{p.transitions_selected} of {p.transitions_total} links"
            run.transitions += f" ({p.inferred_transitions} inferred)"
        elif isinstance(event, st_events.ScenarioFinished):
            if event.elapsed_time > 2:
                print(f"slow: {event.phase.value} {event.recorder.label} {event.elapsed_time:.1f}s")
            for case_id, node in event.recorder.cases.items():
                run.cases[str(event.phase.value)] += 1
                for check in event.recorder.checks.get(case_id, []):
                    if check.failure_info is not None:
                        failure = check.failure_info.failure
                        key = (f"{node.value.method} {node.value.operation.path}", failure.title)
                        run.failures.setdefault(key, (failure.message, check.failure_info.code_sample))
        elif isinstance(event, st_events.NonFatalError):
            run.errors.append(f"{event.label}: {event.info.message}")
        elif isinstance(event, st_events.FatalError):
            run.errors.append(f"fatal: {event.exception!r}")
    return run


def test_no_generated_request_makes_the_server_fail(api, fleet_token, cluster, load_json):
    from django.core.wsgi import get_wsgi_application
    from django.db import connection

    app = api.post("/api/v1/applications/", {"name": "seed", "dag": load_json("topcuoglu.dag.json")}, format="json")
    assert app.status_code == 201, app.data
    auth = {"Authorization": f"Token {fleet_token.plaintext}"}
    config = schemathesis.Config.from_dict(
        {
            "headers": auth,
            "workers": 1,
            "cache": {"enabled": False},  # no state carried between runs (nor a .schemathesis/ directory)
            "seed": 1,
            "continue-on-failure": True,  # every distinct failure, not the first of each operation
            "checks": {"enabled": False, **{name: {"enabled": True} for name in ["not_a_server_error", *EXTRA_CHECKS]}},
            "generation": {"max-examples": MAX_EXAMPLES, "database": "none", "allow-x00": True},
            "phases": {
                "examples": {"enabled": True, "fill-missing": True},
                "coverage": {"enabled": COVERAGE},
                "fuzzing": {"enabled": True},
                "stateful": {
                    "enabled": True,
                    "max-steps": MAX_STEPS,
                    "generation": {"max-examples": MAX_SCENARIOS, "database": "none", "allow-x00": True},
                },
            },
        }
    )
    STATS.clear()
    wsgi = get_wsgi_application()
    schema = schemathesis.openapi.from_wsgi("/api/schema/?format=json", wsgi, config=config, headers=auth)
    assert len(list(schema.get_all_operations())) >= 100
    run = _run(schema)

    report = [f"database: {connection.vendor}; {sum(run.cases.values())} cases"]
    report += [f"  {phase}: {n} cases" for phase, n in sorted(run.cases.items())]
    report += [f"  stateful: {run.transitions}"] + [f"  {k}: {v}" for k, v in sorted(STATS.items())]
    report += [f"{op}: {title}\n{message}\n{sample}" for (op, title), (message, sample) in sorted(run.failures.items())]
    report += run.errors
    print("\n".join(report))
    assert run.cases["fuzzing"] > 0 and run.cases["stateful"] > 0, report
    assert not run.failures and not run.errors, "\n\n".join(report)
