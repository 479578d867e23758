"""A DDS participant that presents itself as ROS 2 nodes do (rmw_cyclonedds_cpp, Humble), for the capture tests
(run by the virtualenv's Python; not a test module).

    python dds_node.py '{"domain": 17, "style": "discovery_info", "nodes": [{"name": "talker", "namespace": "/",
        "publish": [{"topic": "/chatter", "type": "String", "rate": 20, "bytes": 100}],
        "subscribe": [{"topic": "/cmd", "type": "String"}]}]}'

ROS names become DDS topics ``rt/<name>`` with types ``std_msgs::msg::dds_::<Type>_``. With ``"style":
"discovery_info"`` the participant's USER_DATA is ``enclave=/;`` and its nodes, with the GIDs (GUID + 8 zero
bytes) of their readers and writers, are published on ``ros_discovery_info`` (reliable, transient local), as
ROS 2 Foxy and later do; with ``"style": "user_data"`` the one node's name is in USER_DATA
(``name=...;namespace=...;``), as Dashing and Eloquent did. A publication of ``"type": "Plan"`` uses a type the
capture cannot read (``my_msgs::msg::dds_::Plan_``). Prints ``ready`` once everything is created.
"""

import json
import sys
import threading
import time
from dataclasses import dataclass

from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl import types as t
from cyclonedds.pub import DataWriter
from cyclonedds.qos import Policy, Qos
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic


@dataclass
class String_(IdlStruct, typename="std_msgs::msg::dds_::String_"):
    data: str


@dataclass
class Float64_(IdlStruct, typename="std_msgs::msg::dds_::Float64_"):
    data: t.float64


@dataclass
class Plan_(IdlStruct, typename="my_msgs::msg::dds_::Plan_"):
    steps: t.sequence[t.float64]
    goal: str


@dataclass
class Gid_(IdlStruct, typename="rmw_dds_common::msg::dds_::Gid_"):
    data: t.array[t.uint8, 24]


@dataclass
class NodeEntitiesInfo_(IdlStruct, typename="rmw_dds_common::msg::dds_::NodeEntitiesInfo_"):
    node_namespace: t.bounded_str[256]
    node_name: t.bounded_str[256]
    reader_gid_seq: t.sequence[Gid_]
    writer_gid_seq: t.sequence[Gid_]


@dataclass
class ParticipantEntitiesInfo_(IdlStruct, typename="rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_"):
    gid: Gid_
    node_entities_info_seq: t.sequence[NodeEntitiesInfo_]


TYPES = {"String": String_, "Float64": Float64_, "Plan": Plan_}
ROS_QOS = Qos(Policy.Reliability.Reliable(100_000_000), Policy.Durability.Volatile, Policy.History.KeepLast(10))


def gid(guid) -> Gid_:
    return Gid_(data=list(guid.bytes) + [0] * 8)


def message(kind: str, n: int, size: int):
    if kind == "Float64":
        return Float64_(data=float(n))
    if kind == "Plan":
        return Plan_(steps=[1.0, 2.0], goal=f"goal {n}")
    # CDR: 4 header + 4 length + characters + NUL (+ padding): `bytes` is the serialized size
    return String_(data=(f"seq:{n};" + "x" * size)[: max(0, size - 9)])


def main() -> None:
    spec = json.loads(sys.argv[1])
    style = spec.get("style", "discovery_info")
    first = spec["nodes"][0]
    user = (f"name={first['name']};namespace={first.get('namespace', '/')};" if style == "user_data"
            else "enclave=/;")  # fmt: skip
    dp = DomainParticipant(spec["domain"], qos=Qos(Policy.Userdata(user.encode())))
    topics = {}

    def topic(name, kind):
        key = (name, kind)
        if key not in topics:
            topics[key] = Topic(dp, "rt" + name, TYPES[kind])
        return topics[key]

    infos, loops, keep = [], [], []
    for node in spec["nodes"]:
        writers, readers = [], []
        for pub in node.get("publish", []):
            w = DataWriter(dp, topic(pub["topic"], pub["type"]), qos=ROS_QOS)
            writers.append(gid(w.guid))
            loops.append((w, pub))
        for sub in node.get("subscribe", []):
            r = DataReader(dp, topic(sub["topic"], sub["type"]), qos=ROS_QOS)
            readers.append(gid(r.guid))
            keep.append(r)
        infos.append(NodeEntitiesInfo_(node_namespace=node.get("namespace", "/"), node_name=node["name"],
                                       reader_gid_seq=readers, writer_gid_seq=writers))  # fmt: skip
    if style == "discovery_info":
        qos = Qos(
            Policy.Reliability.Reliable(100_000_000), Policy.Durability.TransientLocal, Policy.History.KeepLast(1)
        )
        info_writer = DataWriter(dp, Topic(dp, "ros_discovery_info", ParticipantEntitiesInfo_), qos=qos)
        info_writer.write(ParticipantEntitiesInfo_(gid=gid(dp.guid), node_entities_info_seq=infos))
        keep.append(info_writer)

    def publish(writer, pub):
        period, n = 1.0 / pub["rate"], 0
        next_at = time.monotonic()
        while True:
            writer.write(message(pub["type"], n, pub.get("bytes", 16)))
            n += 1
            next_at += period
            time.sleep(max(0.0, next_at - time.monotonic()))

    for w, pub in loops:
        threading.Thread(target=publish, args=(w, pub), daemon=True).start()
    print("ready", flush=True)
    threading.Event().wait()


if __name__ == "__main__":
    main()
