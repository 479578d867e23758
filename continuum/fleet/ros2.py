"""The live ROS 2 graph of a robot from DDS discovery (Eclipse Cyclone DDS's Python binding), measured where
the message type can be read: ``continuum.rosgraph/v1``.

What ROS 2 puts on DDS (rmw_cyclonedds_cpp, Humble), and how it is read back:

* **Participants** (builtin topic DCPSParticipant): one per ROS 2 context, i.e. per process. Cyclone adds the
  properties ``__Pid`` and ``__Hostname``; ROS 2 up to Eloquent put the node's name in USER_DATA
  (``name=talker;namespace=/;``), later versions put ``enclave=/;`` there and announce nodes on
* **``ros_discovery_info``** (``rmw_dds_common/msg/ParticipantEntitiesInfo``, reliable, transient local): per
  participant, its nodes (namespace, name) with the GIDs of their readers and writers. A GID is the endpoint's
  16-byte DDS GUID padded to 24 bytes (Humble's ``rmw_dds_common/msg/Gid``; Iron and later use 16 bytes and
  are not read here: their nodes fall back to the participant's name).
* **Publications and subscriptions** (DCPSPublication, DCPSSubscription): topic ``rt/<ros name>`` for a ROS
  topic (``rq/``/``rr/`` for services, kept in ``meta.services``), type ``pkg::msg::dds_::Type_`` for
  ``pkg/msg/Type``. Each endpoint belongs to the node whose GID list holds its GUID, else to its participant's
  node.
* **Rates and sizes**: a reader (best effort, so it matches every writer) per topic whose type is one this module
  can read (:data:`KNOWN_TYPES`), for ``duration`` seconds: per writer (``publication_handle``), messages per
  second from the samples' source timestamps (``(n - 1) / (last - first)``, as ``ros2 topic hz``), bytes per
  message as serialized CDR with its 4-byte header (what ``ros2 topic bw`` and rosbag2 count). Other types
  are ``"measured": false`` with the reason.
* **CPU and memory**: from ``/proc`` of the participant's ``__Pid`` when its ``__Hostname`` is this machine's and
  the process's name is the participant's ``__ProcessName``; shared by the nodes of one process.
"""

from __future__ import annotations

import contextlib
import os
import socket
import time
from dataclasses import dataclass, field
from typing import Any

from . import procstat
from .capture_errors import CaptureError

__all__ = ["KNOWN_TYPES", "capture_ros2", "dds_type_to_ros", "ros_topic_name"]

FORMAT = "continuum.rosgraph/v1"
DISCOVERY_TOPIC = "ros_discovery_info"


def ros_topic_name(dds: str) -> tuple[str, str] | None:
    """``rt/scan`` -> ("topic", "/scan"); ``rq/add_two_intsRequest`` -> ("service", "/add_two_ints");
    anything else (DDS topics that are not ROS's) -> None."""
    if dds.startswith("rt/"):
        return "topic", "/" + dds[3:]
    for prefix, suffix in (("rq/", "Request"), ("rr/", "Reply")):
        if dds.startswith(prefix) and dds.endswith(suffix):
            return "service", "/" + dds[len(prefix) : -len(suffix)]
    return None


def dds_type_to_ros(type_name: str) -> str:
    """``std_msgs::msg::dds_::String_`` -> ``std_msgs/msg/String``."""
    parts = [p for p in type_name.split("::") if p != "dds_"]
    if parts and parts[-1].endswith("_"):
        parts[-1] = parts[-1][:-1]
    return "/".join(parts)


#: The ROS message types whose rates and sizes are measured (others are discovered, not measured).
KNOWN_TYPES = ("std_msgs/msg/String", "std_msgs/msg/Float64", "std_msgs/msg/Float32", "std_msgs/msg/Int32",
               "std_msgs/msg/Int64", "std_msgs/msg/Bool")  # fmt: skip


@dataclass
class _Participant:
    key: str
    props: dict[str, str]
    user_name: str | None = None  # from USER_DATA name=...;namespace=...;
    nodes: list[tuple[str, set[bytes], set[bytes]]] = field(default_factory=list)  # (name, readers, writers)


@dataclass
class _Endpoint:
    key: str
    guid: bytes
    participant: str
    topic: str
    type_name: str


def _node_name(namespace: str, name: str) -> str:
    namespace = namespace if namespace.startswith("/") else "/" + namespace
    return (namespace.rstrip("/") + "/" + name) if name else namespace


def _user_data_name(qos: Any) -> str | None:
    from cyclonedds.qos import Policy

    for policy in qos or []:
        if isinstance(policy, Policy.Userdata):
            text = bytes(policy.data).decode("utf-8", "replace")
            fields = dict(p.split("=", 1) for p in text.split(";") if "=" in p)
            if fields.get("name"):
                return _node_name(fields.get("namespace", "/"), fields["name"])
    return None


def _properties(qos: Any) -> dict[str, str]:
    from cyclonedds.qos import Policy

    return {p.key: p.value for p in (qos or []) if isinstance(p, Policy.Property)}


def capture_ros2(domain: int = 0, duration: float = 5.0, *, name: str | None = None,
                 discovery_s: float = 2.0) -> dict[str, Any]:  # fmt: skip
    """Capture and measure the ROS 2 graph of DDS domain ``domain`` (see the module's docstring)."""
    try:
        from cyclonedds.builtin import (
            BuiltinDataReader,
            BuiltinTopicDcpsParticipant,
            BuiltinTopicDcpsPublication,
            BuiltinTopicDcpsSubscription,
        )
        from cyclonedds.core import DDSException
        from cyclonedds.domain import DomainParticipant
        from cyclonedds.qos import Policy, Qos
        from cyclonedds.sub import DataReader
        from cyclonedds.topic import Topic
    except ImportError as exc:  # pragma: no cover - cyclonedds is in requirements-robot.txt
        raise CaptureError(
            f"the Cyclone DDS binding is missing ({exc}): pip install -r requirements-robot.txt"
        ) from None
    from .ros2_types import KNOWN as known
    from .ros2_types import ParticipantEntitiesInfo_ as info_type

    try:
        dp = DomainParticipant(domain)
    except DDSException as exc:
        raise CaptureError(f"cannot join DDS domain {domain} ({exc})") from None
    own = str(dp.guid)
    try:  # the participant is deleted with the process (or when collected): the binding keeps no other handle
        r_part = BuiltinDataReader(dp, BuiltinTopicDcpsParticipant)
        r_pub = BuiltinDataReader(dp, BuiltinTopicDcpsPublication)
        r_sub = BuiltinDataReader(dp, BuiltinTopicDcpsSubscription)
        discovery_qos = Qos(Policy.Reliability.Reliable(0), Policy.Durability.TransientLocal,
                            Policy.History.KeepLast(1000))  # fmt: skip
        r_info = DataReader(dp, Topic(dp, DISCOVERY_TOPIC, info_type), qos=discovery_qos)
        # Discovery is asynchronous: wait, then read what arrived (samples stay in the builtin readers' caches).
        time.sleep(discovery_s)
        participants = {str(s.key): s for s in r_part.read(N=10_000) if s.sample_info.valid_data}
        pubs = [s for s in r_pub.read(N=100_000) if s.sample_info.valid_data]
        subs = [s for s in r_sub.read(N=100_000) if s.sample_info.valid_data]
        infos: list[Any] = [s for s in r_info.take(N=10_000) if s.sample_info.valid_data]  # type: ignore[attr-defined]

        parts = {k: _Participant(k, _properties(s.qos), _user_data_name(s.qos)) for k, s in participants.items()
                 if k != own}  # fmt: skip
        if not parts:
            raise CaptureError(f"no DDS participant answered in domain {domain} within {discovery_s:g} s "
                               "(is ROS 2 running there, and is CYCLONEDDS_URI the robot's?)")  # fmt: skip
        for announced in infos:
            gid = bytes(announced.gid.data[:16])
            key = next((k for k in parts if bytes.fromhex(k.replace("-", "")) == gid), None)
            if key is None:
                continue
            parts[key].nodes = [
                (_node_name(n.node_namespace, n.node_name), {bytes(g.data[:16]) for g in n.reader_gid_seq},
                 {bytes(g.data[:16]) for g in n.writer_gid_seq})
                for n in announced.node_entities_info_seq
            ]  # fmt: skip

        def endpoints(samples: list[Any]) -> list[_Endpoint]:
            out = []
            for s in samples:
                if str(s.participant_key) == own or str(s.participant_key) not in parts:
                    continue
                out.append(_Endpoint(str(s.key), s.key.bytes, str(s.participant_key), s.topic_name, s.type_name))
            return out

        writers, readers = endpoints(pubs), endpoints(subs)
        owner = {e.key: _owner(parts[e.participant], e.guid, e in writers) for e in writers + readers}

        # ---- measurement window: one reader per measurable topic ----
        wanted: dict[str, str] = {}
        for e in writers:
            ros = ros_topic_name(e.topic)
            if ros and ros[0] == "topic" and e.type_name in known:
                wanted[e.topic] = e.type_name
        best_effort = Qos(Policy.Reliability.BestEffort, Policy.Durability.Volatile, Policy.History.KeepLast(256))
        readers_m = {t: DataReader(dp, Topic(dp, t, known[tn]), qos=best_effort) for t, tn in wanted.items()}
        local_pids = {k: pid for k, p in parts.items() if (pid := _local_pid(p)) is not None}
        before = {k: procstat.sample(pid) for k, pid in local_pids.items()}
        stats: dict[tuple[str, int], list[Any]] = {}  # (topic, publication handle) -> [n, bytes, first, last]
        started, end = time.time(), time.monotonic() + duration
        while time.monotonic() < end:
            got = 0
            for topic, reader in readers_m.items():
                for got_sample in reader.take(N=256):
                    sample: Any = got_sample
                    info = sample.sample_info
                    if not info.valid_data:
                        continue
                    got += 1
                    row = stats.setdefault((topic, info.publication_handle), [0, 0, info.source_timestamp, 0])
                    row[0] += 1
                    row[1] += len(sample.serialize())
                    row[3] = info.source_timestamp
            if not got:
                time.sleep(0.005)
        after = {k: procstat.sample(pid) for k, pid in local_pids.items()}
        handle_owner: dict[tuple[str, int], str] = {}
        for topic, reader in readers_m.items():
            for handle in reader.get_matched_publications():
                with contextlib.suppress(DDSException):
                    data = reader.get_matched_publication_data(handle)
                    if data is not None and str(data.key) in owner:
                        handle_owner[(topic, handle)] = owner[str(data.key)]
    except DDSException as exc:
        raise CaptureError(f"DDS domain {domain}: {exc}") from None
    return _document(name or f"ros2-domain-{domain}", domain, parts, writers, readers, owner, known, stats,
                     handle_owner, duration, before, after, local_pids, started)  # fmt: skip


def _owner(part: _Participant, guid: bytes, is_writer: bool) -> str:
    """The node an endpoint belongs to: the node whose GID list holds it, else the participant's node."""
    for name, readers, writers in part.nodes:
        if guid[:16] in (writers if is_writer else readers):
            return name
    if part.user_name:
        return part.user_name
    if len(part.nodes) == 1:
        return part.nodes[0][0]
    process = part.props.get("__ProcessName", "participant")
    return f"/{process}_{part.props.get('__Pid', part.key[:8])}"


def _local_pid(part: _Participant) -> int | None:
    props = part.props
    if props.get("__Hostname") != socket.gethostname():
        return None
    try:
        pid = int(props.get("__Pid", ""))
        comm = (procstat.PROC / str(pid) / "comm").read_text().strip()
    except (ValueError, OSError):
        return None
    # /proc/<pid>/comm is cut at 15 characters
    return pid if comm and props.get("__ProcessName", "")[:15] == comm[:15] else None


def _document(name: str, domain: int, parts: dict[str, _Participant], writers: list[_Endpoint],
              readers: list[_Endpoint], owner: dict[str, str], known: dict[str, Any],
              stats: dict[tuple[str, int], list[Any]], handle_owner: dict[tuple[str, int], str], window: float,
              before: dict, after: dict, local_pids: dict[str, int], started: float) -> dict[str, Any]:  # fmt: skip
    topics: dict[str, dict[str, Any]] = {}
    services: dict[str, set[str]] = {}
    other = set()
    for e, role in [(w, "publishers") for w in writers] + [(r, "subscribers") for r in readers]:
        ros = ros_topic_name(e.topic)
        if ros is None:
            if e.topic != DISCOVERY_TOPIC:
                other.add(e.topic)
            continue
        if ros[0] == "service":
            services.setdefault(ros[1], set()).add(owner[e.key])
            continue
        t = topics.setdefault(ros[1], {"name": ros[1], "publishers": [], "subscribers": [], "dds": e.topic,
                                       "msg_type": dds_type_to_ros(e.type_name), "dds_type": e.type_name})  # fmt: skip
        if owner[e.key] not in t[role]:
            t[role].append(owner[e.key])
    node_names: dict[str, str] = {}  # node -> participant key
    for k, p in parts.items():
        for n, _, _ in p.nodes:
            node_names.setdefault(n, k)
        if p.user_name:
            node_names.setdefault(p.user_name, k)
    for e in writers + readers:
        if ros_topic_name(e.topic):
            node_names.setdefault(owner[e.key], e.participant)

    doc_topics = []
    for t in sorted(topics.values(), key=lambda x: x["name"]):
        dds, dds_type = t.pop("dds"), t.pop("dds_type")
        item = dict(t)
        if not t["publishers"]:
            item.update(rate_hz=0.0, msg_bytes=0.0, measured=False, why_unmeasured="no publisher")
        elif dds_type not in known:
            item.update(rate_hz=0.0, msg_bytes=0.0, measured=False,
                        why_unmeasured=f"type {t['msg_type']} cannot be read here (measured types: "
                                       f"{', '.join(KNOWN_TYPES)})")  # fmt: skip
        else:
            rows: dict[int, list[Any]] = {h: r for (topic, h), r in stats.items() if topic == dds}
            rates: dict[str, float] = {}
            total_n = total_b = 0
            for h, (n, b, first, last) in rows.items():
                who = handle_owner.get((dds, h)) or t["publishers"][0]
                rate = (n - 1) / ((last - first) / 1e9) if n >= 2 and last > first else n / window
                rates[who] = round(rates.get(who, 0.0) + rate, 4)
                total_n, total_b = total_n + int(n), total_b + int(b)
            for p in t["publishers"]:
                rates.setdefault(p, 0.0)
            values = list(rates.values())
            item["rate_hz"] = round(sum(values) / len(values), 4)
            if max(values) - min(values) > 0.05 * max(max(values), 1e-9):
                item["publisher_rates_hz"] = rates
            item["msg_bytes"] = round(total_b / total_n, 2) if total_n else 0.0
            item["measured"] = True
        doc_topics.append(item)

    doc_nodes = []
    for n in sorted(node_names):
        k = node_names[n]
        node_item: dict[str, Any] = {"name": n}
        b, a = before.get(k), after.get(k)
        cores = procstat.cpu_cores(b, a) if b and a else None
        rss = procstat.rss_mib(local_pids[k]) if k in local_pids else None
        if cores is not None and rss is not None:
            node_item.update(cpu=round(cores, 4), memory_mib=round(rss, 2), measured=True)
        else:
            host = parts[k].props.get("__Hostname", "?")
            why = "the process ended during the window" if k in local_pids else f"its process runs on {host}, not here"
            node_item.update(measured=False, why_unmeasured=why)
        doc_nodes.append(node_item)
    return {
        "format": FORMAT,
        "name": name,
        "nodes": doc_nodes,
        "topics": doc_topics,
        "meta": {
            "source": "ros2 capture (DDS discovery)",
            "domain": domain,
            "window_s": window,
            "captured_at": round(started, 3),
            "captured_by": socket.gethostname(),
            "services": {s: sorted(ns) for s, ns in sorted(services.items())},
            "other_dds_topics": sorted(other),
            "pids": {n: parts[k].props.get("__Pid") for n, k in sorted(node_names.items())},
            "environment": {"ROS_DOMAIN_ID": os.environ.get("ROS_DOMAIN_ID")},
        },
    }
