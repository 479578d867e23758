from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar, cast
from uuid import UUID

from attrs import define as _attrs_define
from attrs import field as _attrs_field

if TYPE_CHECKING:
    from ..models.container_deployment import ContainerDeployment
    from ..models.placement_node_traffic_item import PlacementNodeTrafficItem
    from ..models.placement_warnings_item import PlacementWarningsItem


T = TypeVar("T", bound="Placement")


@_attrs_define
class Placement:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        fleet (str):
        clustering (int | None):
        rosgraph (int | None):
        cluster (int | None):
        job (None | UUID):
        policy (str):
        params (Any):
        placed_count (int):
        pending_count (int):
        inter_node_bandwidth (float): bytes/s between containers on different nodes
        baseline (Any): the other policy on the same input: policy, inter_node_bandwidth, placements
        node_traffic (list[PlacementNodeTrafficItem]): bytes/s between each pair of nodes
        warnings (list[PlacementWarningsItem]): what the operator should know: driver-level ROS nodes placed off the
            robot
        plan (Any): PlacementPlan.to_dict(): placements, pending, every node's verdict, metrics
        containers (Any): the resolved continuum.containers/v1 workload that was placed
        cluster_document (Any): the nodes and links placed on (continuum.cluster/v1 snapshot)
        deployments (list[ContainerDeployment]):
        created (datetime.datetime):
    """

    id: int
    fleet: str
    clustering: int | None
    rosgraph: int | None
    cluster: int | None
    job: UUID | None
    policy: str
    params: Any
    placed_count: int
    pending_count: int
    inter_node_bandwidth: float
    baseline: Any
    node_traffic: list[PlacementNodeTrafficItem]
    warnings: list[PlacementWarningsItem]
    plan: Any
    containers: Any
    cluster_document: Any
    deployments: list[ContainerDeployment]
    created: datetime.datetime
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        fleet = self.fleet

        clustering: int | None
        clustering = self.clustering

        rosgraph: int | None
        rosgraph = self.rosgraph

        cluster: int | None
        cluster = self.cluster

        job: str | None
        job = str(self.job) if isinstance(self.job, UUID) else self.job

        policy = self.policy

        params = self.params

        placed_count = self.placed_count

        pending_count = self.pending_count

        inter_node_bandwidth = self.inter_node_bandwidth

        baseline = self.baseline

        node_traffic = []
        for node_traffic_item_data in self.node_traffic:
            node_traffic_item = node_traffic_item_data.to_dict()
            node_traffic.append(node_traffic_item)

        warnings = []
        for warnings_item_data in self.warnings:
            warnings_item = warnings_item_data.to_dict()
            warnings.append(warnings_item)

        plan = self.plan

        containers = self.containers

        cluster_document = self.cluster_document

        deployments = []
        for deployments_item_data in self.deployments:
            deployments_item = deployments_item_data.to_dict()
            deployments.append(deployments_item)

        created = self.created.isoformat()

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "fleet": fleet,
                "clustering": clustering,
                "rosgraph": rosgraph,
                "cluster": cluster,
                "job": job,
                "policy": policy,
                "params": params,
                "placed_count": placed_count,
                "pending_count": pending_count,
                "inter_node_bandwidth": inter_node_bandwidth,
                "baseline": baseline,
                "node_traffic": node_traffic,
                "warnings": warnings,
                "plan": plan,
                "containers": containers,
                "cluster_document": cluster_document,
                "deployments": deployments,
                "created": created,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.container_deployment import ContainerDeployment
        from ..models.placement_node_traffic_item import PlacementNodeTrafficItem
        from ..models.placement_warnings_item import PlacementWarningsItem

        d = dict(src_dict)
        id = d.pop("id")

        fleet = d.pop("fleet")

        def _parse_clustering(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        clustering = _parse_clustering(d.pop("clustering"))

        def _parse_rosgraph(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        rosgraph = _parse_rosgraph(d.pop("rosgraph"))

        def _parse_cluster(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        cluster = _parse_cluster(d.pop("cluster"))

        def _parse_job(data: object) -> UUID | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                job_type_0 = UUID(data)

                return job_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(UUID | None, data)

        job = _parse_job(d.pop("job"))

        policy = d.pop("policy")

        params = d.pop("params")

        placed_count = d.pop("placed_count")

        pending_count = d.pop("pending_count")

        inter_node_bandwidth = d.pop("inter_node_bandwidth")

        baseline = d.pop("baseline")

        node_traffic = []
        _node_traffic = d.pop("node_traffic")
        for node_traffic_item_data in _node_traffic:
            node_traffic_item = PlacementNodeTrafficItem.from_dict(node_traffic_item_data)

            node_traffic.append(node_traffic_item)

        warnings = []
        _warnings = d.pop("warnings")
        for warnings_item_data in _warnings:
            warnings_item = PlacementWarningsItem.from_dict(warnings_item_data)

            warnings.append(warnings_item)

        plan = d.pop("plan")

        containers = d.pop("containers")

        cluster_document = d.pop("cluster_document")

        deployments = []
        _deployments = d.pop("deployments")
        for deployments_item_data in _deployments:
            deployments_item = ContainerDeployment.from_dict(deployments_item_data)

            deployments.append(deployments_item)

        created = datetime.datetime.fromisoformat(d.pop("created"))

        placement = cls(
            id=id,
            fleet=fleet,
            clustering=clustering,
            rosgraph=rosgraph,
            cluster=cluster,
            job=job,
            policy=policy,
            params=params,
            placed_count=placed_count,
            pending_count=pending_count,
            inter_node_bandwidth=inter_node_bandwidth,
            baseline=baseline,
            node_traffic=node_traffic,
            warnings=warnings,
            plan=plan,
            containers=containers,
            cluster_document=cluster_document,
            deployments=deployments,
            created=created,
        )

        placement.additional_properties = d
        return placement

    @property
    def additional_keys(self) -> list[str]:
        return list(self.additional_properties.keys())

    def __getitem__(self, key: str) -> Any:
        return self.additional_properties[key]

    def __setitem__(self, key: str, value: Any) -> None:
        self.additional_properties[key] = value

    def __delitem__(self, key: str) -> None:
        del self.additional_properties[key]

    def __contains__(self, key: str) -> bool:
        return key in self.additional_properties
