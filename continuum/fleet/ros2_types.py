# mypy: ignore-errors
# (the binding's annotations, array[uint8, 24] and the like, are run-time type descriptions mypy cannot read)
"""The DDS types the ROS 2 capture reads (:mod:`.ros2`), as rmw_cyclonedds_cpp (Humble) names and lays them out.

No ``from __future__ import annotations`` here: the Cyclone DDS binding resolves these annotations at run
time, by name, in this module's namespace.
"""

from dataclasses import dataclass

from cyclonedds.idl import IdlStruct
from cyclonedds.idl import types as t


@dataclass
class String_(IdlStruct, typename="std_msgs::msg::dds_::String_"):
    data: str


@dataclass
class Float64_(IdlStruct, typename="std_msgs::msg::dds_::Float64_"):
    data: t.float64


@dataclass
class Float32_(IdlStruct, typename="std_msgs::msg::dds_::Float32_"):
    data: t.float32


@dataclass
class Int32_(IdlStruct, typename="std_msgs::msg::dds_::Int32_"):
    data: t.int32


@dataclass
class Int64_(IdlStruct, typename="std_msgs::msg::dds_::Int64_"):
    data: t.int64


@dataclass
class Bool_(IdlStruct, typename="std_msgs::msg::dds_::Bool_"):
    data: bool


@dataclass
class Gid_(IdlStruct, typename="rmw_dds_common::msg::dds_::Gid_"):
    """Humble's GID: the 16-byte GUID padded to 24 bytes (Iron and later: 16 bytes, not read here)."""

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


#: The measurable message types by DDS type name.
KNOWN = {c.__idl_typename__: c for c in (String_, Float64_, Float32_, Int32_, Int64_, Bool_)}
