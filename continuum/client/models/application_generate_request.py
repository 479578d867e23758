from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.dag_class_enum import DagClassEnum, check_dag_class_enum
from ..models.generator_enum import GeneratorEnum, check_generator_enum
from ..types import UNSET, Unset

T = TypeVar("T", bound="ApplicationGenerateRequest")


@_attrs_define
class ApplicationGenerateRequest:
    """A seeded synthetic DAG: the thesis' ``thesis`` generator (Tree/Linear OpenVX-like CPU/GPU DAGs,
    spec 01 section 8.2) or the HEFT literature's ``layered`` random graphs (Topcuoglu et al. 2002).

        Attributes:
            generator (GeneratorEnum): * `thesis` - thesis
                * `layered` - layered
            fleet (str | Unset):
            seed (int | Unset):  Default: 0.
            n (int | Unset): tasks
            dag_class (DagClassEnum | Unset): * `tree` - tree
                * `linear` - linear
            shape (float | Unset): layered: height/width shape (alpha)
            out_degree (float | Unset): layered: mean out-degree
            ccr (float | Unset): layered: communication-to-computation ratio
            mean_cost (float | Unset): layered: mean task cost
            processors (int | Unset): layered: per-processor costs p0.. (unrelated)
            heterogeneity (float | Unset): layered: beta
            name (str | Unset):
            description (str | Unset):  Default: ''.
    """

    generator: GeneratorEnum
    fleet: str | Unset = UNSET
    seed: int | Unset = 0
    n: int | Unset = UNSET
    dag_class: DagClassEnum | Unset = UNSET
    shape: float | Unset = UNSET
    out_degree: float | Unset = UNSET
    ccr: float | Unset = UNSET
    mean_cost: float | Unset = UNSET
    processors: int | Unset = UNSET
    heterogeneity: float | Unset = UNSET
    name: str | Unset = UNSET
    description: str | Unset = ""
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        generator: str = self.generator

        fleet = self.fleet

        seed = self.seed

        n = self.n

        dag_class: str | Unset = UNSET
        if not isinstance(self.dag_class, Unset):
            dag_class = self.dag_class

        shape = self.shape

        out_degree = self.out_degree

        ccr = self.ccr

        mean_cost = self.mean_cost

        processors = self.processors

        heterogeneity = self.heterogeneity

        name = self.name

        description = self.description

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "generator": generator,
            }
        )
        if fleet is not UNSET:
            field_dict["fleet"] = fleet
        if seed is not UNSET:
            field_dict["seed"] = seed
        if n is not UNSET:
            field_dict["n"] = n
        if dag_class is not UNSET:
            field_dict["dag_class"] = dag_class
        if shape is not UNSET:
            field_dict["shape"] = shape
        if out_degree is not UNSET:
            field_dict["out_degree"] = out_degree
        if ccr is not UNSET:
            field_dict["ccr"] = ccr
        if mean_cost is not UNSET:
            field_dict["mean_cost"] = mean_cost
        if processors is not UNSET:
            field_dict["processors"] = processors
        if heterogeneity is not UNSET:
            field_dict["heterogeneity"] = heterogeneity
        if name is not UNSET:
            field_dict["name"] = name
        if description is not UNSET:
            field_dict["description"] = description

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        generator = check_generator_enum(d.pop("generator"))

        fleet = d.pop("fleet", UNSET)

        seed = d.pop("seed", UNSET)

        n = d.pop("n", UNSET)

        _dag_class = d.pop("dag_class", UNSET)
        dag_class: DagClassEnum | Unset
        dag_class = UNSET if isinstance(_dag_class, Unset) else check_dag_class_enum(_dag_class)

        shape = d.pop("shape", UNSET)

        out_degree = d.pop("out_degree", UNSET)

        ccr = d.pop("ccr", UNSET)

        mean_cost = d.pop("mean_cost", UNSET)

        processors = d.pop("processors", UNSET)

        heterogeneity = d.pop("heterogeneity", UNSET)

        name = d.pop("name", UNSET)

        description = d.pop("description", UNSET)

        application_generate_request = cls(
            generator=generator,
            fleet=fleet,
            seed=seed,
            n=n,
            dag_class=dag_class,
            shape=shape,
            out_degree=out_degree,
            ccr=ccr,
            mean_cost=mean_cost,
            processors=processors,
            heterogeneity=heterogeneity,
            name=name,
            description=description,
        )

        application_generate_request.additional_properties = d
        return application_generate_request

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
