"""The fleet command line: ``python -m continuum.fleet [--server URL --token T] COMMAND ...``.

Exit status: 0 done; 1 the server failed, could not be reached, or the job failed or timed out; 2 bad input
(arguments, files, or a request the server refused with 4xx), with one line on stderr. ``--json`` prints the
result as JSON on stdout. Long operations show a progress bar on stderr (a terminal, or ``--progress``).
"""

from __future__ import annotations

import argparse
import csv
import json
import logging
import math
import os
import sys
import uuid
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from tqdm import tqdm

from .api import MAX_EVENTS, ApiError, Fleet, JobFailed, MissReport
from .capture_errors import CaptureError
from .rosbag import BagError, describe_bag, events_from_bag, rosgraph_from_bag

#: Largest file the command line reads (a DAG, a ROS graph, an events CSV is read as a stream instead).
MAX_FILE = 64 * 1024 * 1024
#: Longest measurement window of ``capture`` (seconds).
MAX_CAPTURE_S = 3600


class BadInput(Exception):
    """The caller's mistake: exit 2 with one line."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, not usage + message
        raise BadInput(message)


def _to_dict(obj: Any) -> Any:
    return obj.to_dict() if hasattr(obj, "to_dict") else obj


def _emit(args: argparse.Namespace, obj: Any, human: str) -> None:
    print(json.dumps(_to_dict(obj), default=str, indent=None) if args.json else human)


def _read(path: str) -> bytes:
    p = Path(path)
    try:
        if p.stat().st_size > MAX_FILE:
            raise BadInput(f"{path}: larger than {MAX_FILE // 2**20} MiB")
        return p.read_bytes()
    except OSError as exc:
        raise BadInput(f"{path}: {exc.strerror or exc}") from None


def _json_file(path: str) -> Any:
    try:
        return json.loads(_read(path))
    except ValueError as exc:
        raise BadInput(f"{path}: not JSON ({exc})") from None


def _fleet(args: argparse.Namespace) -> Fleet:
    server = args.server or os.environ.get("CONTINUUM_SERVER")
    token = args.token or os.environ.get("CONTINUUM_TOKEN")
    if not server or not token:
        raise BadInput("give --server and --token (or CONTINUUM_SERVER and CONTINUUM_TOKEN)")
    try:
        return Fleet(server, token, timeout=args.timeout_http, retries=args.retries)
    except ValueError as exc:
        raise BadInput(str(exc)) from None


def _bar(args: argparse.Namespace, **kw: Any) -> tqdm:
    return tqdm(file=sys.stderr, disable=None if args.progress is None else not args.progress, **kw)


def _follow(args: argparse.Namespace, fleet: Fleet, job: Any) -> Any:
    """Wait for a job with a 0-100 bar that shows its message."""
    with _bar(args, total=100, unit="%", desc=job.kind) as bar:

        def show(j: Any) -> None:
            bar.update(max(0, j.progress - bar.n))
            bar.set_postfix_str((j.message or j.state)[:60], refresh=True)

        return fleet.wait(job, poll=args.poll, timeout=args.wait_timeout, on_progress=show)


# ---- commands ----------------------------------------------------------------------------------------------
def cmd_upload(args: argparse.Namespace) -> None:
    data = _read(args.file)
    with _fleet(args) as fleet:
        if args.kind == "rosgraph":
            row = fleet.upload_rosgraph(data, Path(args.file).name, name=args.name, fmt=args.format)
            _emit(args, row, f"ROS graph {row.id} {row.name!r}: {row.node_count} nodes, {row.topic_count} topics")
        else:
            row = fleet.upload_application(data, Path(args.file).name, name=args.name, fmt=args.format)
            _emit(args, row, f"application {row.id} {row.name!r}")


def cmd_bag_graph(args: argparse.Namespace) -> None:
    names = _json_file(args.nodes) if args.nodes else {}
    if not isinstance(names, dict):
        raise BadInput(f'{args.nodes}: expected {{"publishers": {{topic: [node]}}, "subscribers": {{...}}}}')
    doc = rosgraph_from_bag(args.bag, name=args.name, publishers=names.get("publishers"),
                            subscribers=names.get("subscribers"), topics=args.topic or None)  # fmt: skip
    if not args.upload:
        print(json.dumps(doc, indent=2))
        return
    with _fleet(args) as fleet:
        row = fleet.upload_rosgraph(doc, f"{doc['name']}.json", name=args.name or doc["name"])
        _emit(args, row, f"ROS graph {row.id} {row.name!r}: {row.node_count} nodes, {row.topic_count} topics")


def _cell(text: str) -> bool | float | str:
    low = text.strip().lower()
    if low in ("true", "false"):
        return low == "true"
    try:
        value = float(text)
    except ValueError:
        return text.strip()
    if not math.isfinite(value):
        raise BadInput(f"value {text!r} is not finite")
    return int(value) if value.is_integer() and "." not in text and "e" not in low else value


def csv_events(path: str) -> Iterator[list[Any]]:
    """Events from a CSV: ``variable,value,timestamp`` rows, or a trace as ``stl_check`` reads it (a ``time``
    column in ms and one column per signal; an empty cell is no event)."""
    try:
        f = open(path, newline="")  # noqa: SIM115  # closed below; a generator keeps it open while streaming
    except OSError as exc:
        raise BadInput(f"{path}: {exc.strerror or exc}") from None
    with f:
        rows = csv.reader(f)
        header = [h.strip() for h in next(rows, [])]
        if not header:
            raise BadInput(f"{path}: empty file")
        long = header[:3] == ["variable", "value", "timestamp"]
        if not long and (not header or header[0] != "time" or len(header) < 2):
            raise BadInput(f"{path}: header must be 'variable,value,timestamp' or 'time,<signal>,...'")
        for n, row in enumerate(rows, start=2):
            if not row:
                continue
            if len(row) != len(header):
                raise BadInput(f"{path}: line {n} has {len(row)} fields, the header {len(header)}")
            try:
                stamp = float(row[2] if long else row[0])
            except ValueError:
                raise BadInput(f"{path}: line {n}: time {row[2] if long else row[0]!r} is not a number") from None
            if not math.isfinite(stamp) or stamp < 0:
                raise BadInput(f"{path}: line {n}: time must be a finite number of ms >= 0")
            try:
                if long:
                    yield [row[0].strip(), _cell(row[1]), stamp]
                else:
                    for name, text in zip(header[1:], row[1:], strict=True):
                        if text.strip():
                            yield [name, _cell(text), stamp]
            except BadInput as exc:
                raise BadInput(f"{path}: line {n}: {exc}") from None


def _post(args: argparse.Namespace, events: Callable[[], Iterator[list[Any]]], source: str) -> None:
    """Post the events in batches. They are read twice: a first pass validates them all (and counts them for the
    progress bar), so that a bad line stops the command before any batch is sent, not half-way."""
    total = sum(1 for _ in events())
    if not total:
        raise BadInput(f"{source}: no events")
    if args.cluster is None:
        raise BadInput("give --cluster (or --dry-run)")
    with _fleet(args) as fleet, _bar(args, unit="ev", desc=source, total=total) as bar:
        last = [0]

        def step(sent: int, answer: dict) -> None:
            bar.update(sent - last[0])
            last[0] = sent

        answers = fleet.post_events(args.cluster, events(), now=args.now, batch_size=args.batch_size, on_batch=step)
    violations = sum(len(a.get("violations", [])) for a in answers if isinstance(a, dict))
    _emit(args, {"batches": answers, "events": last[0], "violations": violations},
          f"{last[0]} events in {len(answers)} batches, {violations} violations")  # fmt: skip


def cmd_events(args: argparse.Namespace) -> None:
    _post(args, lambda: csv_events(args.csv), Path(args.csv).name)


def cmd_bag_events(args: argparse.Namespace) -> None:
    skipped: dict[str, None] = {}  # one line per topic that cannot be decoded, said once at the end

    def events() -> Iterator[list[Any]]:
        return events_from_bag(args.bag, topics=args.topic or None, signals=args.signal or None,
                               on_skip=lambda line: skipped.setdefault(line))  # fmt: skip

    if args.dry_run:
        for e in events():
            print(json.dumps(e))
    else:
        _post(args, events, Path(args.bag).name)
    for line in skipped:
        print(f"warning: {line}", file=sys.stderr)


def cmd_bag_info(args: argparse.Namespace) -> None:
    info = describe_bag(args.bag)
    lines = [f"{info['kind']} {info['path']}: {len(info['topics'])} topics over {info['window_s']:.3f} s"]
    for t in info["topics"]:
        state = "decodable" if t["decodable"] else f"not decodable: {t['why']}"
        lines.append(f"  {t['name']} ({t['msg_type']}): {t['messages']} messages, {t['rate_hz']:g} Hz, "
                     f"{t['msg_bytes']:g} B; {state}")  # fmt: skip
    _emit(args, info, "\n".join(lines))


def cmd_capture(args: argparse.Namespace) -> None:
    if args.duration > MAX_CAPTURE_S:
        raise BadInput(f"--duration must be at most {MAX_CAPTURE_S} s")
    if args.upload:
        fleet = _fleet(args)  # before the window: a missing token fails at once, not after minutes of measuring
    try:
        if args.ros1:
            from .ros1 import capture_ros1

            doc = capture_ros1(args.ros1, args.duration, name=args.name, topics=args.topic or None)
        else:
            from .ros2 import capture_ros2

            doc = capture_ros2(args.domain, args.duration, name=args.name)
    except CaptureError as exc:
        raise BadInput(str(exc)) from None
    text = json.dumps(doc, indent=2)
    if args.out:
        try:
            Path(args.out).write_text(text + "\n")
        except OSError as exc:
            raise BadInput(f"{args.out}: {exc.strerror or exc}") from None
    if args.upload:
        with fleet:
            row = fleet.upload_rosgraph(doc, f"{doc['name']}.json", name=args.name or doc["name"])
        _emit(args, row, f"ROS graph {row.id} {row.name!r}: {row.node_count} nodes, {row.topic_count} topics")
    elif args.out:
        measured = sum(1 for t in doc["topics"] if t.get("measured"))
        _emit(args, {"out": args.out, "nodes": len(doc["nodes"]), "topics": len(doc["topics"]), "measured": measured},
              f"{args.out}: {len(doc['nodes'])} nodes, {len(doc['topics'])} topics ({measured} measured)")  # fmt: skip
    else:
        print(text)


def cmd_report(args: argparse.Namespace) -> None:
    if args.missed_period < 0 or args.missed_total < args.missed_period:
        raise BadInput("need 0 <= --missed-period <= --missed-total")
    report = MissReport(args.node, args.container, args.missed_period, args.missed_total, pod=args.pod or "",
                        miss_at=args.miss_at, report_id=args.id or uuid.uuid4().hex)  # fmt: skip
    with _fleet(args) as fleet:
        answer = fleet.report_misses([report], cluster=args.cluster)[0]
    stored = answer.get("stored") if isinstance(answer, dict) else None
    _emit(args, answer, f"report {report.report_id}: stored {stored}, violations {answer.get('violations', '?')}")


def cmd_schedule(args: argparse.Namespace) -> None:
    request: dict[str, Any] = {"algorithm": args.algorithm}
    if args.cluster is not None:
        request["cluster"] = args.cluster
    if args.platform:
        request["platform"] = _json_file(args.platform)
    for key in ("frames", "fps", "batch"):
        if getattr(args, key) is not None:
            request[key] = getattr(args, key)
    with _fleet(args) as fleet:
        try:
            job = fleet.schedule(args.application, **request)
        except ValueError as exc:
            raise BadInput(str(exc)) from None
        if not args.wait:
            _emit(args, job, f"job {job.id} {job.state}")
            return
        done = _follow(args, fleet, job)
    _emit(args, done, f"job {done.id} {done.state}: {done.message} {done.result_url}".rstrip())


def cmd_push(args: argparse.Namespace) -> None:
    with _fleet(args) as fleet:
        job = fleet.push(args.schedule)
        done = _follow(args, fleet, job) if args.wait else job
    _emit(args, done, f"job {done.id} {done.state}: {done.message}")


def cmd_wait(args: argparse.Namespace) -> None:
    with _fleet(args) as fleet:
        try:
            job = fleet.job(args.job)
        except ValueError:
            raise BadInput(f"{args.job!r} is not a job id") from None
        done = _follow(args, fleet, job)
    _emit(args, done, f"job {done.id} {done.state}: {done.message} {done.result_url}".rstrip())


# ---- parser ----------------------------------------------------------------------------------------------
def _positive(kind: type) -> Any:
    def parse(text: str) -> Any:
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a {kind.__name__}") from None
        if not (isinstance(value, int) or math.isfinite(value)) or value <= 0:
            raise argparse.ArgumentTypeError(f"{text!r} must be positive")
        return value

    return parse


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="python -m continuum.fleet", description=__doc__.splitlines()[0])
    p.add_argument("--server", help="the server's URL (default: $CONTINUUM_SERVER)")
    p.add_argument("--token", help="a fleet API token (default: $CONTINUUM_TOKEN)")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="progress bars on stderr (default: when stderr is a terminal)")  # fmt: skip
    p.add_argument("--timeout-http", type=_positive(float), default=30.0, help="seconds per request")
    p.add_argument("--retries", type=int, choices=range(0, 11), default=4, metavar="0..10",
                   help="tries when the server cannot be reached or is busy (429/503), with back-off")  # fmt: skip
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    up = sub.add_parser("upload", help="upload a DAG (application) or a ROS graph file")
    up.add_argument("kind", choices=["application", "rosgraph"])
    up.add_argument("file")
    up.add_argument("--name")
    up.add_argument("--format", help="the file's format (default: guessed by the server)")
    up.set_defaults(func=cmd_upload)

    bi = sub.add_parser("bag-info", help="what a recording holds: topics, types, counts, rates, decodable or why not")
    bi.add_argument("bag", help="a rosbag1 .bag file, a rosbag2 directory, or a .db3/.mcap file")
    bi.set_defaults(func=cmd_bag_info)

    bg = sub.add_parser("bag-graph", help="a continuum.rosgraph/v1 document from a recording (rosbag1 or rosbag2)")
    bg.add_argument("bag", help="a rosbag1 .bag file, a rosbag2 directory, or a .db3/.mcap file")
    bg.add_argument("--nodes", help='JSON {"publishers": {topic: [node]}, "subscribers": {topic: [node]}}')
    bg.add_argument("--topic", action="append", help="only this topic (repeatable)")
    bg.add_argument("--name")
    bg.add_argument("--upload", action="store_true", help="upload it (else print it)")
    bg.set_defaults(func=cmd_bag_graph)

    for name, helptext in (("events", "stream STL events from a CSV file"),
                           ("bag-events", "stream STL events from a recording (rosbag1 or rosbag2)")):  # fmt: skip
        ev = sub.add_parser(name, help=helptext)
        if name == "events":
            ev.add_argument("csv", help="variable,value,timestamp rows, or a time column plus one per signal")
            ev.set_defaults(func=cmd_events)
        else:
            ev.add_argument("bag")
            ev.add_argument("--topic", action="append", help="only this topic (repeatable)")
            ev.add_argument("--signal", action="append", help="only this signal, e.g. odom.twist.twist.linear.x")
            ev.add_argument("--dry-run", action="store_true", help="print the events as JSON lines, send nothing")
            ev.set_defaults(func=cmd_bag_events)
        ev.add_argument("--cluster", type=_positive(int), required=name == "events")
        ev.add_argument("--now", type=float, help="advance the monitors' clock to this time (ms) at the end")
        ev.add_argument("--batch-size", type=_positive(int), default=1000, help=f"events per request (<= {MAX_EVENTS})")

    ca = sub.add_parser("capture", help="capture a live ROS graph with measured rates (continuum.rosgraph/v1)")
    source = ca.add_mutually_exclusive_group(required=True)
    source.add_argument("--ros1", metavar="MASTER_URI", help="a ROS 1 master, e.g. http://robot:11311/")
    source.add_argument("--ros2", action="store_true", help="ROS 2 over DDS (Cyclone DDS discovery)")
    ca.add_argument("--domain", type=int, choices=range(0, 233), default=0, metavar="0..232",
                    help="the ROS 2 domain id (ROS_DOMAIN_ID)")  # fmt: skip
    ca.add_argument("--duration", type=_positive(float), default=5.0, help="measurement window in seconds")
    ca.add_argument("--topic", action="append", help="only this topic (repeatable; ROS 1)")
    ca.add_argument("--name", help="the graph's name")
    dest = ca.add_mutually_exclusive_group()
    dest.add_argument("--out", help="write the graph to this file (else print it)")
    dest.add_argument("--upload", action="store_true", help="upload it to the server")
    ca.set_defaults(func=cmd_capture)

    rp = sub.add_parser("report", help="report missed deadlines of a container")
    rp.add_argument("--node", required=True)
    rp.add_argument("--container", required=True)
    rp.add_argument("--pod")
    rp.add_argument("--missed-period", type=int, required=True)
    rp.add_argument("--missed-total", type=int, required=True)
    rp.add_argument("--miss-at", type=float, help="when the first miss of the period happened (epoch seconds)")
    rp.add_argument("--cluster", type=_positive(int))
    rp.add_argument("--id", help="the report's idempotency key (default: a new UUID)")
    rp.set_defaults(func=cmd_report)

    sc = sub.add_parser("schedule", help="schedule an application (and wait for the job)")
    sc.add_argument("application", type=_positive(int))
    sc.add_argument("--algorithm", default="heft")
    target = sc.add_mutually_exclusive_group(required=True)
    target.add_argument("--cluster", type=_positive(int))
    target.add_argument("--platform", help="a platform JSON file")
    sc.add_argument("--frames", type=_positive(int))
    sc.add_argument("--fps", type=_positive(float))
    sc.add_argument("--batch", type=_positive(int))
    sc.add_argument("--wait", action="store_true", help="follow the job to its end with a progress bar")
    sc.set_defaults(func=cmd_schedule)

    pu = sub.add_parser("push", help="bind a schedule's pods in Kubernetes (and wait)")
    pu.add_argument("schedule", type=_positive(int))
    pu.add_argument("--wait", action="store_true")
    pu.set_defaults(func=cmd_push)

    wa = sub.add_parser("wait", help="follow a job to its end with a progress bar")
    wa.add_argument("job")
    wa.set_defaults(func=cmd_wait)

    for cmd in (sc, pu, wa):
        cmd.add_argument("--poll", type=_positive(float), default=0.5, help="seconds between looks at the job")
        cmd.add_argument("--wait-timeout", type=_positive(float), help="give up after this many seconds (exit 1)")
    return p


def main(argv: list[str] | None = None) -> int:
    # httpx logs every request at INFO: noise on a robot's stderr, where only errors and progress belong.
    logging.getLogger("httpx").setLevel(logging.WARNING)
    try:
        args = build_parser().parse_args(argv)
        if getattr(args, "batch_size", 1) > MAX_EVENTS:
            raise BadInput(f"--batch-size must be at most {MAX_EVENTS}")
        args.func(args)
        return 0
    except BadInput as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except BagError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except ApiError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2 if exc.status is not None and 400 <= exc.status < 500 and exc.status != 429 else 1
    except (JobFailed, TimeoutError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return 130
