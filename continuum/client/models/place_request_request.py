from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.policy_enum import PolicyEnum, check_policy_enum
from ..types import UNSET, Unset

if TYPE_CHECKING:
    from ..models.place_request_request_overrides import PlaceRequestRequestOverrides
    from ..models.place_request_request_weights import PlaceRequestRequestWeights


T = TypeVar("T", bound="PlaceRequestRequest")


@_attrs_define
class PlaceRequestRequest:
    """Place containers on the nodes of a cluster: a clustering's containers (with per-container
    ``overrides``) or a ``continuum.containers/v1`` document (optionally with the ROS graph for bandwidth).

        Attributes:
            cluster (int):
            policy (PolicyEnum | Unset): * `superclustering` - superclustering
                * `default-kubernetes` - default-kubernetes
                * `default` - default
                * `kubernetes` - kubernetes
                * `k8s` - k8s Default: 'superclustering'.
            clustering (int | Unset):
            containers (Any | Unset): a continuum.containers/v1 document
            rosgraph (int | Unset): with 'containers': bandwidth by Def. 3.2.1
            overrides (PlaceRequestRequestOverrides | Unset): container -> {cpu, memory_mib, priority, archs, node,
                tolerations...}
            archs (list[str] | Unset):
            weights (PlaceRequestRequestWeights | Unset):
            seed (int | Unset): tie-break seed of the default-Kubernetes policy Default: 0.
            overhead_mib (float | Unset): runtime memory per container Default: 0.0.
            compare (bool | Unset): also run the other policy for comparison Default: True.
            drivers_on_robot (bool | Unset): keep containers holding driver-level (or robot-pinned) ROS nodes on the robot's
                boards
            robot_label (str | Unset): key=value label of the robot's boards (default zone=robot)
    """

    cluster: int
    policy: PolicyEnum | Unset = "superclustering"
    clustering: int | Unset = UNSET
    containers: Any | Unset = UNSET
    rosgraph: int | Unset = UNSET
    overrides: PlaceRequestRequestOverrides | Unset = UNSET
    archs: list[str] | Unset = UNSET
    weights: PlaceRequestRequestWeights | Unset = UNSET
    seed: int | Unset = 0
    overhead_mib: float | Unset = 0.0
    compare: bool | Unset = True
    drivers_on_robot: bool | Unset = UNSET
    robot_label: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        cluster = self.cluster

        policy: str | Unset = UNSET
        if not isinstance(self.policy, Unset):
            policy = self.policy

        clustering = self.clustering

        containers = self.containers

        rosgraph = self.rosgraph

        overrides: dict[str, Any] | Unset = UNSET
        if not isinstance(self.overrides, Unset):
            overrides = self.overrides.to_dict()

        archs: list[str] | Unset = UNSET
        if not isinstance(self.archs, Unset):
            archs = self.archs

        weights: dict[str, Any] | Unset = UNSET
        if not isinstance(self.weights, Unset):
            weights = self.weights.to_dict()

        seed = self.seed

        overhead_mib = self.overhead_mib

        compare = self.compare

        drivers_on_robot = self.drivers_on_robot

        robot_label = self.robot_label

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "cluster": cluster,
            }
        )
        if policy is not UNSET:
            field_dict["policy"] = policy
        if clustering is not UNSET:
            field_dict["clustering"] = clustering
        if containers is not UNSET:
            field_dict["containers"] = containers
        if rosgraph is not UNSET:
            field_dict["rosgraph"] = rosgraph
        if overrides is not UNSET:
            field_dict["overrides"] = overrides
        if archs is not UNSET:
            field_dict["archs"] = archs
        if weights is not UNSET:
            field_dict["weights"] = weights
        if seed is not UNSET:
            field_dict["seed"] = seed
        if overhead_mib is not UNSET:
            field_dict["overhead_mib"] = overhead_mib
        if compare is not UNSET:
            field_dict["compare"] = compare
        if drivers_on_robot is not UNSET:
            field_dict["drivers_on_robot"] = drivers_on_robot
        if robot_label is not UNSET:
            field_dict["robot_label"] = robot_label

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.place_request_request_overrides import PlaceRequestRequestOverrides
        from ..models.place_request_request_weights import PlaceRequestRequestWeights

        d = dict(src_dict)
        cluster = d.pop("cluster")

        _policy = d.pop("policy", UNSET)
        policy: PolicyEnum | Unset
        policy = UNSET if isinstance(_policy, Unset) else check_policy_enum(_policy)

        clustering = d.pop("clustering", UNSET)

        containers = d.pop("containers", UNSET)

        rosgraph = d.pop("rosgraph", UNSET)

        _overrides = d.pop("overrides", UNSET)
        overrides: PlaceRequestRequestOverrides | Unset
        overrides = UNSET if isinstance(_overrides, Unset) else PlaceRequestRequestOverrides.from_dict(_overrides)

        archs = cast(list[str], d.pop("archs", UNSET))

        _weights = d.pop("weights", UNSET)
        weights: PlaceRequestRequestWeights | Unset
        weights = UNSET if isinstance(_weights, Unset) else PlaceRequestRequestWeights.from_dict(_weights)

        seed = d.pop("seed", UNSET)

        overhead_mib = d.pop("overhead_mib", UNSET)

        compare = d.pop("compare", UNSET)

        drivers_on_robot = d.pop("drivers_on_robot", UNSET)

        robot_label = d.pop("robot_label", UNSET)

        place_request_request = cls(
            cluster=cluster,
            policy=policy,
            clustering=clustering,
            containers=containers,
            rosgraph=rosgraph,
            overrides=overrides,
            archs=archs,
            weights=weights,
            seed=seed,
            overhead_mib=overhead_mib,
            compare=compare,
            drivers_on_robot=drivers_on_robot,
            robot_label=robot_label,
        )

        place_request_request.additional_properties = d
        return place_request_request

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
