"""``python -m continuum.agent run ...``: the node agent's command line (see the package docstring)."""

from __future__ import annotations

import argparse
import contextlib
import errno
import json
import os
import signal
import socket
import sys
import time
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Sequence
from typing import Any, NoReturn

from .admission import measure
from .privileges import User, default_user, drop_for_agent, parse_user
from .report import Reporter, Target, http_problem, urlopen
from .sched import DeadlineParams, refusal
from .trace import run_traced

PROG = "continuum.agent"
#: Exit statuses of the agent itself (otherwise it exits with the command's status, 128+N if signal N killed it).
EXIT_USAGE = 2
EXIT_UNAVAILABLE = 69
EXIT_KERNEL_REJECTED = 75
EXIT_NOT_PERMITTED = 77
EXIT_NOT_EXECUTABLE = 126
EXIT_NOT_FOUND = 127
#: Start-up overruns are expected for this many periods after exec unless told otherwise: measured here, a Python
#: command that sleeps under a 5 ms / 50 ms reservation overran 6 and 12 times while its interpreter started.
DEFAULT_WARMUP_PERIODS = 20
FORWARDED = (signal.SIGTERM, signal.SIGINT, signal.SIGHUP, signal.SIGQUIT, signal.SIGUSR1, signal.SIGUSR2)


class UsageError(Exception):
    """Bad input: exit status 2 and one line on stderr."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        raise UsageError(message)

    def parse_known_args(  # type: ignore[override]
        self, args: Sequence[str] | None = None, namespace: argparse.Namespace | None = None
    ) -> tuple[argparse.Namespace, list[str]]:
        # The subcommand's parser is called with its own arguments: each level joins its own options' values.
        return super().parse_known_args(attach_values(self, sys.argv[1:] if args is None else list(args)), namespace)


def _option(ap: argparse.ArgumentParser, text: str) -> argparse.Action | None:
    """The option ``text`` names in ``ap`` (exactly, or as argparse's unambiguous ``--`` abbreviation)."""
    actions = {s: a for a in ap._actions for s in a.option_strings}
    if text in actions:
        return actions[text]
    if text.startswith("--") and len(text) > 2:
        hits = {a for s, a in actions.items() if s.startswith(text)}
        return hits.pop() if len(hits) == 1 else None
    return None


def attach_values(ap: argparse.ArgumentParser, argv: list[str]) -> list[str]:
    """``--token -Xy...`` as ``--token=-Xy...``: argparse takes any word that starts with '-' for an option, so
    ``--token T`` failed with "expected one argument" (exit 2) for the 1 key in 64 that ``secrets.token_urlsafe``
    starts with '-'. A word after an option that takes one value is that value unless it is an option of ``ap``
    itself (then the value is missing, and argparse says so). Stops at COMMAND (the first positional) or ``--``."""
    out: list[str] = []
    words = iter(argv)
    for word in words:
        out.append(word)
        if word == "--" or not word.startswith("-") or word == "-":
            out.extend(words)  # COMMAND ARGS... (or the subcommand and its arguments): never rewritten
            break
        action = None if "=" in word else _option(ap, word)
        if action is None or action.nargs is not None:  # a flag, a --name=value, or unknown (argparse says)
            continue
        value = next(words, None)
        if value is None:
            break
        if value.startswith("-") and value != "-" and not _is_option(ap, value):
            out[-1] = f"{word}={value}"
        else:
            out.append(value)
    return out


def _is_option(ap: argparse.ArgumentParser, word: str) -> bool:
    return word == "--" or _option(ap, word.split("=", 1)[0] if word.startswith("--") else word) is not None


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0 < value < float("inf"):
        raise argparse.ArgumentTypeError(f"{text!r} must be a positive number")
    return value


def _non_negative(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0 <= value < float("inf"):
        raise argparse.ArgumentTypeError(f"{text!r} must be a number >= 0")
    return value


def _user(text: str) -> User:
    try:
        return parse_user(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _port(text: str) -> int:
    if not text.isdigit() or int(text) > 65535:
        raise argparse.ArgumentTypeError(f"{text!r} is not a port number (0-65535)")
    return int(text)


def _port_env(name: str) -> int | None:
    text = os.environ.get(name, "").strip()
    return int(text) if text.isdigit() and int(text) <= 65535 else None


def parser() -> argparse.ArgumentParser:
    ap = _Parser(prog=f"python -m {PROG}", description="Continuum's node agent (RT-Kube, thesis 3.4).")
    sub = ap.add_subparsers(dest="action", required=True)
    run = sub.add_parser("run", help="run COMMAND under SCHED_DEADLINE, count and report its runtime overruns")
    timing = run.add_argument_group("timing (ms; default: the RealTime object's, with the node's WCET as runtime)")
    timing.add_argument("--runtime-ms", type=_positive, help="runtime (WCET on this node)")
    timing.add_argument("--deadline-ms", type=_positive, help="relative deadline")
    timing.add_argument("--period-ms", type=_positive, help="period")
    warm = timing.add_mutually_exclusive_group()
    warm.add_argument("--warmup-ms", type=_non_negative,
                      help="start-up after exec whose overruns are counted apart, never as misses (default: the "
                           f"RealTime's warmup_ms, else {DEFAULT_WARMUP_PERIODS} periods); the command may end it "
                           "early by writing to the descriptor in CONTINUUM_READY_FD")  # fmt: skip
    warm.add_argument("--warmup-periods", type=_non_negative, help="the same, in periods")
    api = run.add_argument_group("reporting to Continuum")
    api.add_argument("--realtime", metavar="NAME", help="the RealTime object: timing fetched, named in reports")
    api.add_argument("--namespace", help="the RealTime object's namespace (when the name is ambiguous)")
    api.add_argument("--cluster", type=int, help="cluster id (default: the RealTime object's, or the fleet's only)")
    api.add_argument("--server", default=os.environ.get("CONTINUUM_SERVER"),
                     help="base URL, e.g. http://continuum:8000 (env CONTINUUM_SERVER)")  # fmt: skip
    api.add_argument("--allow-http", action="store_true",
                     help="allow a plain http:// --server (the token then crosses the network in clear)")  # fmt: skip
    api.add_argument("--token", default=os.environ.get("CONTINUUM_TOKEN"),
                     help="fleet API token (env CONTINUUM_TOKEN; better: arguments show in ps)")  # fmt: skip
    api.add_argument("--node", default=os.environ.get("NODE_NAME") or socket.gethostname(),
                     help="node name in reports (env NODE_NAME, else the host name)")  # fmt: skip
    api.add_argument("--container", help="containerName in reports (default: the RealTime name, else COMMAND's)")
    api.add_argument("--pod", default=os.environ.get("POD_NAME", ""), help="pod name in reports (env POD_NAME)")
    api.add_argument("--interval", type=_positive, default=0.5, help="seconds between reports (1/f_c; 0.5)")
    api.add_argument("--max-backoff", type=_positive, default=10.0, help="longest wait between retries (10 s)")
    api.add_argument("--flush-timeout", type=float, default=10.0,
                     help="seconds to deliver the last reports once COMMAND ended (10)")  # fmt: skip
    api.add_argument("--http-timeout", type=_positive, default=5.0, help="seconds per request (5)")
    run.add_argument("--tracer-priority", type=int, default=1, choices=range(0, 100), metavar="0-99",
                     help="SCHED_FIFO priority of the agent's tracing thread (1; 0: leave it SCHED_OTHER)")  # fmt: skip
    run.add_argument("--user", type=_user, default=None, metavar="USER[:GID]",
                     help="who COMMAND runs as, with no capability (default: nobody if the agent is root)")  # fmt: skip
    obs = run.add_argument_group("metrics")
    obs.add_argument("--metrics-port", type=_port, default=_port_env("CONTINUUM_AGENT_METRICS_PORT"),
                     help="serve /metrics on this port (env CONTINUUM_AGENT_METRICS_PORT; 0: any)")  # fmt: skip
    obs.add_argument("--metrics-addr", default=os.environ.get("CONTINUUM_AGENT_METRICS_ADDR", "127.0.0.1"),
                     help="address to serve /metrics on (127.0.0.1; 0.0.0.0 in a pod)")  # fmt: skip
    obs.add_argument("--metrics-linger", type=float, default=0.0,
                     help="seconds to keep serving /metrics after COMMAND ended (0)")  # fmt: skip
    run.add_argument("--json", action="store_true", help="print one JSON object on stdout at the end")
    run.add_argument("command", nargs=argparse.REMAINDER, help="-- COMMAND ARGS...")
    adm = sub.add_parser("admission", help="this node's admissible deadline bandwidth, read from its kernel "
                         "(printed; reported to Continuum with --server)")  # fmt: skip
    adm.add_argument("--probe", action="store_true", help="measure it with deadline tasks even when it can be read")
    adm.add_argument("--server", default=os.environ.get("CONTINUUM_SERVER"), help="base URL (env CONTINUUM_SERVER)")
    adm.add_argument("--allow-http", action="store_true", help="allow a plain http:// --server")
    adm.add_argument("--token", default=os.environ.get("CONTINUUM_TOKEN"), help="fleet token (env CONTINUUM_TOKEN)")
    adm.add_argument("--node", default=os.environ.get("NODE_NAME") or socket.gethostname(),
                     help="node name (env NODE_NAME, else the host name)")  # fmt: skip
    adm.add_argument("--cluster", type=int, help="cluster id (default: the fleet's only one)")
    adm.add_argument("--http-timeout", type=_positive, default=30.0, help="seconds for the request (30)")
    return ap


def _get_json(server: str, token: str, path: str, params: dict[str, Any], timeout: float) -> Any:
    url = server.rstrip("/") + path + "?" + urllib.parse.urlencode({k: v for k, v in params.items() if v is not None})
    request = urllib.request.Request(url, headers={"Authorization": f"Token {token}", "Accept": "application/json"})
    with urlopen(request, timeout=timeout) as response:
        return json.loads(response.read())


def fetch_realtime(args: argparse.Namespace) -> dict[str, Any]:
    """The RealTime object named ``args.realtime`` (exactly one among the caller's fleets' clusters)."""
    params = {"search": args.realtime, "cluster": args.cluster, "namespace": args.namespace, "limit": 100}
    try:
        page = _get_json(args.server, args.token, "/api/v1/realtimes/", params, args.http_timeout)
    except urllib.error.HTTPError as exc:
        raise UsageError(f"cannot read RealTime {args.realtime!r} from {args.server}: {http_problem(exc)}") from exc
    except (OSError, ValueError) as exc:
        raise ConnectionError(f"cannot reach {args.server} to read RealTime {args.realtime!r}: {exc}") from exc
    rows = page.get("results", page) if isinstance(page, dict) else page
    hits = [r for r in rows if isinstance(r, dict) and r.get("name") == args.realtime]
    if not hits:
        raise UsageError(f"no RealTime {args.realtime!r} among your fleets' clusters")
    if len(hits) > 1:
        where = ", ".join(f"cluster {r.get('cluster')} namespace {r.get('namespace')}" for r in hits)
        raise UsageError(f"RealTime {args.realtime!r} is ambiguous ({where}): give --cluster / --namespace")
    return hits[0]


def resolve(args: argparse.Namespace) -> tuple[DeadlineParams, Target | None, dict[str, Any]]:
    """The deadline parameters and where reports go; UsageError names the problem."""
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command:
        raise UsageError("no COMMAND given (run ... -- COMMAND ARGS...)")
    args.command = command
    _check_server(args)
    info: dict[str, Any] = {}
    timing = {"runtime": args.runtime_ms, "deadline": args.deadline_ms, "period": args.period_ms}
    cluster = args.cluster
    if args.realtime:
        if not args.server:
            raise UsageError("--realtime needs --server and --token to read the object")
        row = fetch_realtime(args)
        wcets = {w.get("node"): w.get("wcet") for w in row.get("wcets", [])}
        if timing["runtime"] is None and args.node not in wcets:
            raise UsageError(f"RealTime {args.realtime!r} has no WCET for node {args.node!r} (it has: "
                             f"{', '.join(map(str, wcets)) or 'none'}); give --node or --runtime-ms")  # fmt: skip
        defaults = {"runtime": wcets.get(args.node), "deadline": row.get("deadline"), "period": row.get("period")}
        timing = {k: v if v is not None else defaults[k] for k, v in timing.items()}
        cluster = cluster if cluster is not None else row.get("cluster")
        info["realtime"] = {"id": row.get("id"), "name": row.get("name"), "namespace": row.get("namespace"),
                            "cluster": row.get("cluster"), "criticality": row.get("criticality")}  # fmt: skip
    if args.warmup_ms is None and args.warmup_periods is None and args.realtime:
        warm = row.get("warmup_ms")
        if isinstance(warm, int | float) and not isinstance(warm, bool) and 0 <= warm < float("inf"):
            args.warmup_ms = float(warm)
    missing = [f"--{k}-ms" for k, v in timing.items() if v is None]
    if missing:
        raise UsageError(f"missing {', '.join(missing)} (or --realtime with --server to read them)")
    params = DeadlineParams.from_ms(float(timing["runtime"]), float(timing["deadline"]), float(timing["period"]))
    problem = params.problem()
    if problem:
        raise UsageError(problem)
    container = args.container or args.realtime or os.path.basename(command[0])
    target = None
    if args.server:
        if not args.node:
            raise UsageError("no node name: give --node (or NODE_NAME)")
        target = Target(args.server, args.token, args.node, container, args.pod, cluster, args.http_timeout)
    if args.warmup_ms is None:
        periods = DEFAULT_WARMUP_PERIODS if args.warmup_periods is None else args.warmup_periods
        args.warmup_ms = periods * params.period_ns / 1e6
    info.update(node=args.node, container=container)
    return params, target, info


def _check_server(args: argparse.Namespace) -> None:
    if args.server and not args.token:
        raise UsageError("--server needs --token (or CONTINUUM_TOKEN)")
    if args.server:
        scheme = urllib.parse.urlsplit(args.server).scheme
        if scheme not in ("http", "https"):
            raise UsageError(f"--server {args.server!r} must be an http(s) URL")
        if scheme == "http" and not args.allow_http:
            raise UsageError(f"--server {args.server!r} is plain http: the token would cross in clear; use https "
                             "or give --allow-http")  # fmt: skip


def admission(args: argparse.Namespace) -> int:
    """``admission``: measure, print one JSON object, and report it (exit 69 if the report failed)."""
    try:
        found = measure(use_probe=args.probe)
    except OSError as exc:
        print(f"{PROG}: cannot read the kernel's admission: {exc}", file=sys.stderr)
        return EXIT_UNAVAILABLE
    doc = found.as_dict() | {"node": args.node}
    status = 0
    if args.server:
        body: dict[str, Any] = {"node": args.node, "capacity": found.capacity, "cpus": found.cpus,
                                "source": found.source[:200], "kernel": found.kernel[:100]}  # fmt: skip
        if args.cluster is not None:
            body["cluster"] = args.cluster
        request = urllib.request.Request(
            args.server.rstrip("/") + "/api/v1/rt-admissions/", data=json.dumps(body).encode(), method="POST",
            headers={"Content-Type": "application/json", "Authorization": f"Token {args.token}"},
        )  # fmt: skip
        try:
            with urlopen(request, timeout=args.http_timeout) as response:
                doc["reported"] = json.loads(response.read() or b"{}")
        except urllib.error.HTTPError as exc:
            doc["report_error"] = http_problem(exc)
        except (OSError, ValueError) as exc:
            doc["report_error"] = f"{type(exc).__name__}: {exc}"
        if "report_error" in doc:
            print(f"{PROG}: the admission was not reported: {doc['report_error']}", file=sys.stderr)
            status = EXIT_UNAVAILABLE
    print(json.dumps(doc), flush=True)
    return status


def main(argv: Sequence[str] | None = None) -> int:
    try:
        args = parser().parse_args(argv)
        if args.action == "admission":
            _check_server(args)
            return admission(args)
        params, target, info = resolve(args)
    except UsageError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except ConnectionError as exc:
        print(f"{PROG}: {exc}", file=sys.stderr)
        return EXIT_UNAVAILABLE
    return run(args, params, target, info)


def run(args: argparse.Namespace, params: DeadlineParams, target: Target | None, info: dict[str, Any]) -> int:
    reporter = Reporter(target, interval=args.interval, max_backoff=args.max_backoff)
    child = {"pid": 0}
    collector: Any = None
    if args.metrics_port is not None:
        # prometheus_client only when metrics are asked for: the agent otherwise needs the standard library alone
        # (it runs with a node's or an image's own Python).
        from .metrics import AgentCollector

        collector = AgentCollector(reporter, info.get("node") or "", info.get("container") or "")
    exposed: list[Any] = []

    def expose() -> None:
        """The metrics server, once (after the fork: the command never shares its thread)."""
        if args.metrics_port is None or exposed:
            return
        try:
            from .metrics import serve as serve_metrics

            server, port = serve_metrics(collector, args.metrics_port, args.metrics_addr)
        except OSError as exc:
            print(f"{PROG}: cannot serve metrics on {args.metrics_addr}:{args.metrics_port}: {exc}", file=sys.stderr)
            exposed.append(None)
            return
        exposed.append(server)
        print(f"{PROG}: metrics on http://{args.metrics_addr}:{port}/metrics", file=sys.stderr, flush=True)

    def forward(sig: int, _frame: object) -> None:
        if child["pid"]:
            with contextlib.suppress(ProcessLookupError):
                os.kill(child["pid"], sig)

    previous = {sig: signal.signal(sig, forward) for sig in FORWARDED}

    tracer: dict[str, Any] = {"policy": "other", "caps": None}
    user = args.user or default_user()
    # The command may say it is ready (ends its warm-up) by writing to this pipe.
    ready_r, ready_w = os.pipe()
    os.set_inheritable(ready_w, True)
    os.set_blocking(ready_r, False)
    # The command never sees the fleet token (it could send it anywhere).
    env = {k: v for k, v in os.environ.items() if k != "CONTINUUM_TOKEN"}
    env["CONTINUUM_READY_FD"] = str(ready_w)
    warm: dict[str, Any] = {"until": float("inf"), "ready": False, "agent_w_closed": False}

    def overrun(at: float) -> None:
        if not warm["ready"]:
            with contextlib.suppress(BlockingIOError):
                warm["ready"] = bool(os.read(ready_r, 64))
        if not warm["ready"] and time.monotonic() < warm["until"]:
            reporter.startup_overrun(at)
        else:
            reporter.overrun(at)

    def started(pid: int) -> None:
        warm["until"] = time.monotonic() + args.warmup_ms / 1000  # from the exec: the command's first instruction
        os.close(ready_w)  # the command has its copy
        warm["agent_w_closed"] = True
        child["pid"] = pid
        tracer["caps"] = drop_for_agent()  # before any other thread: they inherit what this one keeps
        expose()
        reporter.start()  # after the fork: the child never shares the reporter's thread
        # A command stopped at its SIGXCPU waits for this thread: it must get the CPU at once, also when SCHED_OTHER
        # work (a stress, other pods) fills what the deadline tasks leave. Only this thread (not the reporter).
        if args.tracer_priority:
            try:
                os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(args.tracer_priority))
                tracer["policy"] = f"fifo:{args.tracer_priority}"
            except OSError:
                pass  # e.g. no RT runtime in this cgroup: trace at SCHED_OTHER (reported in the JSON)

    began = time.monotonic()
    try:
        outcome = run_traced(args.command, params, overrun, started, user=user, env=env)
    except OSError as exc:
        print(f"{PROG}: cannot trace the command: {exc}", file=sys.stderr)
        return EXIT_UNAVAILABLE
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        os.close(ready_r)
        if not warm["agent_w_closed"]:
            os.close(ready_w)
    reason = None
    if outcome.refused is not None:
        status, text = refusal(outcome.refused)
        reason = f"{text} ({errno.errorcode.get(outcome.refused, outcome.refused)})"
        if outcome.refused == errno.EBUSY:
            if collector is not None:
                collector.rejected = True
            reporter.kernel_rejected(reason)
        reporter.start()
        print(f"{PROG}: {reason}", file=sys.stderr)
    elif outcome.drop_errno is not None:
        status = EXIT_NOT_PERMITTED
        reason = f"cannot drop privileges to uid {user.uid} gid {user.gid}: {os.strerror(outcome.drop_errno)}"
        reporter.start()
        print(f"{PROG}: {reason}", file=sys.stderr)
    elif outcome.exec_errno is not None:
        status = EXIT_NOT_FOUND if outcome.exec_errno == errno.ENOENT else EXIT_NOT_EXECUTABLE
        reason = f"cannot run {args.command[0]!r}: {os.strerror(outcome.exec_errno)}"
        reporter.start()
        print(f"{PROG}: {reason}", file=sys.stderr)
    elif outcome.signal is not None:
        status = 128 + outcome.signal
    else:
        status = outcome.exit_code or 0
    duration = time.monotonic() - began
    ran = outcome.refused is None and outcome.exec_errno is None and outcome.drop_errno is None
    reporter.close(args.flush_timeout)
    expose()  # the command may have been refused before it ran: the totals are still served
    if exposed and exposed[0] is not None and args.metrics_linger > 0:
        time.sleep(args.metrics_linger)
    result = {
        "overruns": reporter.overruns,
        "startup_overruns": reporter.startup_overruns,
        "startup_reported": reporter.startup_acknowledged,
        "warmup_ms": args.warmup_ms,
        "ready_signalled": warm["ready"],
        "kernel_rejected": outcome.refused == errno.EBUSY,
        "exit_code": outcome.exit_code if ran else None,
        "signal": outcome.signal if outcome.refused is None else None,
        "reported": reporter.acknowledged,
        "pending": reporter.pending if target is not None else 0,
        "rejection_reported": reporter.rejection_acknowledged,
        "reports_acknowledged": reporter.reports_acknowledged,
        "server_violations": reporter.server_violations,
        "report_failures": reporter.failures,
        "report_error": reporter.fatal or (reporter.last_error if reporter.pending else None),
        "reporting": target is not None,
        "status": status,
        "reason": reason,
        "runtime_ms": params.runtime_ns / 1e6,
        "deadline_ms": params.deadline_ns / 1e6,
        "period_ms": params.period_ns / 1e6,
        "bandwidth": params.bandwidth,
        "duration_s": round(duration, 3),
        "tracer_policy": tracer["policy"],
        "command_uid": user.uid,
        "command_gid": user.gid,
        "agent_capabilities": tracer["caps"],
        **info,
    }
    if target is not None and reporter.pending:
        print(f"{PROG}: {reporter.pending} overruns not delivered: {result['report_error']}", file=sys.stderr)
    if args.json:
        sys.stdout.flush()
        print(json.dumps(result), flush=True)
    return status
