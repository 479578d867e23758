from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

if TYPE_CHECKING:
    from ..models.cluster_document_link_request import ClusterDocumentLinkRequest
    from ..models.cluster_document_node_request import ClusterDocumentNodeRequest


T = TypeVar("T", bound="ClusterImportRequest")


@_attrs_define
class ClusterImportRequest:
    """A ``continuum.cluster/v1`` document that creates a cluster with its nodes and links at once.

    Attributes:
        name (str):
        nodes (list[ClusterDocumentNodeRequest]):
        fleet (str | Unset):
        description (str | Unset):  Default: ''.
        kubeconfig (str | Unset):  Default: ''.
        kube_context (str | Unset):  Default: ''.
        namespace (str | Unset):  Default: 'continuum'.
        links (list[ClusterDocumentLinkRequest] | Unset):
    """

    name: str
    nodes: list[ClusterDocumentNodeRequest]
    fleet: str | Unset = UNSET
    description: str | Unset = ""
    kubeconfig: str | Unset = ""
    kube_context: str | Unset = ""
    namespace: str | Unset = "continuum"
    links: list[ClusterDocumentLinkRequest] | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        name = self.name

        nodes = []
        for nodes_item_data in self.nodes:
            nodes_item = nodes_item_data.to_dict()
            nodes.append(nodes_item)

        fleet = self.fleet

        description = self.description

        kubeconfig = self.kubeconfig

        kube_context = self.kube_context

        namespace = self.namespace

        links: list[dict[str, Any]] | Unset = UNSET
        if not isinstance(self.links, Unset):
            links = []
            for links_item_data in self.links:
                links_item = links_item_data.to_dict()
                links.append(links_item)

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "name": name,
                "nodes": nodes,
            }
        )
        if fleet is not UNSET:
            field_dict["fleet"] = fleet
        if description is not UNSET:
            field_dict["description"] = description
        if kubeconfig is not UNSET:
            field_dict["kubeconfig"] = kubeconfig
        if kube_context is not UNSET:
            field_dict["kube_context"] = kube_context
        if namespace is not UNSET:
            field_dict["namespace"] = namespace
        if links is not UNSET:
            field_dict["links"] = links

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.cluster_document_link_request import ClusterDocumentLinkRequest
        from ..models.cluster_document_node_request import ClusterDocumentNodeRequest

        d = dict(src_dict)
        name = d.pop("name")

        nodes = []
        _nodes = d.pop("nodes")
        for nodes_item_data in _nodes:
            nodes_item = ClusterDocumentNodeRequest.from_dict(nodes_item_data)

            nodes.append(nodes_item)

        fleet = d.pop("fleet", UNSET)

        description = d.pop("description", UNSET)

        kubeconfig = d.pop("kubeconfig", UNSET)

        kube_context = d.pop("kube_context", UNSET)

        namespace = d.pop("namespace", UNSET)

        _links = d.pop("links", UNSET)
        links: list[ClusterDocumentLinkRequest] | Unset = UNSET
        if _links is not UNSET:
            links = []
            for links_item_data in _links:
                links_item = ClusterDocumentLinkRequest.from_dict(links_item_data)

                links.append(links_item)

        cluster_import_request = cls(
            name=name,
            nodes=nodes,
            fleet=fleet,
            description=description,
            kubeconfig=kubeconfig,
            kube_context=kube_context,
            namespace=namespace,
            links=links,
        )

        cluster_import_request.additional_properties = d
        return cluster_import_request

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
