from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar, cast
from uuid import UUID

from attrs import define as _attrs_define
from attrs import field as _attrs_field

if TYPE_CHECKING:
    from ..models.clustering_container_bandwidth_item import ClusteringContainerBandwidthItem
    from ..models.clustering_containers_item import ClusteringContainersItem
    from ..models.clustering_dockerfiles_type_0 import ClusteringDockerfilesType0


T = TypeVar("T", bound="Clustering")


@_attrs_define
class Clustering:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        fleet (str):
        rosgraph (int):
        rosgraph_name (str):
        job (None | UUID):
        requested_containers (int):
        container_count (int):
        params (Any): clustering and image options as given
        containers (list[ClusteringContainersItem]):
        inter_container_bandwidth (float): bytes/s left between containers
        intra_container_bandwidth (float): bytes/s kept inside containers
        container_bandwidth (list[ClusteringContainerBandwidthItem]): bytes/s between each pair of containers
        result (Any): Clustering.to_dict(): containers with their ROS nodes, passes, bandwidth
        images (Any): ImagePlan.to_dict(), when ROS nodes list packages
        disk_before_mib (float | None):
        disk_after_mib (float | None):
        dockerfiles (ClusteringDockerfilesType0 | None): archive URLs, when there is an image plan
        created (datetime.datetime):
    """

    id: int
    fleet: str
    rosgraph: int
    rosgraph_name: str
    job: UUID | None
    requested_containers: int
    container_count: int
    params: Any
    containers: list[ClusteringContainersItem]
    inter_container_bandwidth: float
    intra_container_bandwidth: float
    container_bandwidth: list[ClusteringContainerBandwidthItem]
    result: Any
    images: Any
    disk_before_mib: float | None
    disk_after_mib: float | None
    dockerfiles: ClusteringDockerfilesType0 | None
    created: datetime.datetime
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        from ..models.clustering_dockerfiles_type_0 import ClusteringDockerfilesType0

        id = self.id

        fleet = self.fleet

        rosgraph = self.rosgraph

        rosgraph_name = self.rosgraph_name

        job: str | None
        job = str(self.job) if isinstance(self.job, UUID) else self.job

        requested_containers = self.requested_containers

        container_count = self.container_count

        params = self.params

        containers = []
        for containers_item_data in self.containers:
            containers_item = containers_item_data.to_dict()
            containers.append(containers_item)

        inter_container_bandwidth = self.inter_container_bandwidth

        intra_container_bandwidth = self.intra_container_bandwidth

        container_bandwidth = []
        for container_bandwidth_item_data in self.container_bandwidth:
            container_bandwidth_item = container_bandwidth_item_data.to_dict()
            container_bandwidth.append(container_bandwidth_item)

        result = self.result

        images = self.images

        disk_before_mib: float | None
        disk_before_mib = self.disk_before_mib

        disk_after_mib: float | None
        disk_after_mib = self.disk_after_mib

        dockerfiles: dict[str, Any] | None
        if isinstance(self.dockerfiles, ClusteringDockerfilesType0):
            dockerfiles = self.dockerfiles.to_dict()
        else:
            dockerfiles = self.dockerfiles

        created = self.created.isoformat()

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "fleet": fleet,
                "rosgraph": rosgraph,
                "rosgraph_name": rosgraph_name,
                "job": job,
                "requested_containers": requested_containers,
                "container_count": container_count,
                "params": params,
                "containers": containers,
                "inter_container_bandwidth": inter_container_bandwidth,
                "intra_container_bandwidth": intra_container_bandwidth,
                "container_bandwidth": container_bandwidth,
                "result": result,
                "images": images,
                "disk_before_mib": disk_before_mib,
                "disk_after_mib": disk_after_mib,
                "dockerfiles": dockerfiles,
                "created": created,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.clustering_container_bandwidth_item import ClusteringContainerBandwidthItem
        from ..models.clustering_containers_item import ClusteringContainersItem
        from ..models.clustering_dockerfiles_type_0 import ClusteringDockerfilesType0

        d = dict(src_dict)
        id = d.pop("id")

        fleet = d.pop("fleet")

        rosgraph = d.pop("rosgraph")

        rosgraph_name = d.pop("rosgraph_name")

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

        requested_containers = d.pop("requested_containers")

        container_count = d.pop("container_count")

        params = d.pop("params")

        containers = []
        _containers = d.pop("containers")
        for containers_item_data in _containers:
            containers_item = ClusteringContainersItem.from_dict(containers_item_data)

            containers.append(containers_item)

        inter_container_bandwidth = d.pop("inter_container_bandwidth")

        intra_container_bandwidth = d.pop("intra_container_bandwidth")

        container_bandwidth = []
        _container_bandwidth = d.pop("container_bandwidth")
        for container_bandwidth_item_data in _container_bandwidth:
            container_bandwidth_item = ClusteringContainerBandwidthItem.from_dict(container_bandwidth_item_data)

            container_bandwidth.append(container_bandwidth_item)

        result = d.pop("result")

        images = d.pop("images")

        def _parse_disk_before_mib(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        disk_before_mib = _parse_disk_before_mib(d.pop("disk_before_mib"))

        def _parse_disk_after_mib(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        disk_after_mib = _parse_disk_after_mib(d.pop("disk_after_mib"))

        def _parse_dockerfiles(data: object) -> ClusteringDockerfilesType0 | None:
            if data is None:
                return data
            try:
                if not isinstance(data, dict):
                    raise TypeError()
                dockerfiles_type_0 = ClusteringDockerfilesType0.from_dict(data)

                return dockerfiles_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(ClusteringDockerfilesType0 | None, data)

        dockerfiles = _parse_dockerfiles(d.pop("dockerfiles"))

        created = datetime.datetime.fromisoformat(d.pop("created"))

        clustering = cls(
            id=id,
            fleet=fleet,
            rosgraph=rosgraph,
            rosgraph_name=rosgraph_name,
            job=job,
            requested_containers=requested_containers,
            container_count=container_count,
            params=params,
            containers=containers,
            inter_container_bandwidth=inter_container_bandwidth,
            intra_container_bandwidth=intra_container_bandwidth,
            container_bandwidth=container_bandwidth,
            result=result,
            images=images,
            disk_before_mib=disk_before_mib,
            disk_after_mib=disk_after_mib,
            dockerfiles=dockerfiles,
            created=created,
        )

        clustering.additional_properties = d
        return clustering

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
