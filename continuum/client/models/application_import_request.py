from __future__ import annotations

from collections.abc import Mapping
from io import BytesIO
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from .. import types
from ..models.application_import_format_enum import ApplicationImportFormatEnum, check_application_import_format_enum
from ..models.duplicate_enum import DuplicateEnum, check_duplicate_enum
from ..types import UNSET, File, Unset

T = TypeVar("T", bound="ApplicationImportRequest")


@_attrs_define
class ApplicationImportRequest:
    """Upload a DAG file: continuum JSON, WfCommons WfFormat 1.5, Pegasus DAX, Kasahara STG or the thesis CSV.

    The format is ``format`` when given, else the file name's (``.stg``, ``.dax``/``.xml``, ``.csv``), else
    guessed from the content. ``options`` (a JSON object) go to the reader, e.g. STG's
    ``{"ccr": 1, "processors": 4, "heterogeneity": 0.5, "seed": 7}``.

        Attributes:
            file (File):
            fleet (str | Unset):
            format_ (ApplicationImportFormatEnum | Unset): * `continuum` - continuum
                * `dax` - dax
                * `stg` - stg
                * `thesis_csv` - thesis_csv
                * `wfformat` - wfformat
            options (str | Unset): reader options as a JSON object, e.g. STG: {"ccr": 1, "processors": 4, "heterogeneity":
                0.5}
            name (str | Unset):
            description (str | Unset):  Default: ''.
            duplicate (DuplicateEnum | Unset): * `refuse` - refuse
                * `allow` - allow Default: 'refuse'.
    """

    file: File
    fleet: str | Unset = UNSET
    format_: ApplicationImportFormatEnum | Unset = UNSET
    options: str | Unset = UNSET
    name: str | Unset = UNSET
    description: str | Unset = ""
    duplicate: DuplicateEnum | Unset = "refuse"
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        file = self.file.to_tuple()

        fleet = self.fleet

        format_: str | Unset = UNSET
        if not isinstance(self.format_, Unset):
            format_ = self.format_

        options = self.options

        name = self.name

        description = self.description

        duplicate: str | Unset = UNSET
        if not isinstance(self.duplicate, Unset):
            duplicate = self.duplicate

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "file": file,
            }
        )
        if fleet is not UNSET:
            field_dict["fleet"] = fleet
        if format_ is not UNSET:
            field_dict["format"] = format_
        if options is not UNSET:
            field_dict["options"] = options
        if name is not UNSET:
            field_dict["name"] = name
        if description is not UNSET:
            field_dict["description"] = description
        if duplicate is not UNSET:
            field_dict["duplicate"] = duplicate

        return field_dict

    def to_multipart(self) -> types.RequestFiles:
        files: types.RequestFiles = []

        files.append(("file", self.file.to_tuple()))

        if not isinstance(self.fleet, Unset):
            files.append(("fleet", (None, str(self.fleet).encode(), "text/plain")))

        if not isinstance(self.format_, Unset):
            files.append(("format", (None, str(self.format_).encode(), "text/plain")))

        if not isinstance(self.options, Unset):
            files.append(("options", (None, str(self.options).encode(), "text/plain")))

        if not isinstance(self.name, Unset):
            files.append(("name", (None, str(self.name).encode(), "text/plain")))

        if not isinstance(self.description, Unset):
            files.append(("description", (None, str(self.description).encode(), "text/plain")))

        if not isinstance(self.duplicate, Unset):
            files.append(("duplicate", (None, str(self.duplicate).encode(), "text/plain")))

        for prop_name, prop in self.additional_properties.items():
            files.append((prop_name, (None, str(prop).encode(), "text/plain")))

        return files

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        file = File(payload=BytesIO(d.pop("file")))

        fleet = d.pop("fleet", UNSET)

        _format_ = d.pop("format", UNSET)
        format_: ApplicationImportFormatEnum | Unset
        format_ = UNSET if isinstance(_format_, Unset) else check_application_import_format_enum(_format_)

        options = d.pop("options", UNSET)

        name = d.pop("name", UNSET)

        description = d.pop("description", UNSET)

        _duplicate = d.pop("duplicate", UNSET)
        duplicate: DuplicateEnum | Unset
        duplicate = UNSET if isinstance(_duplicate, Unset) else check_duplicate_enum(_duplicate)

        application_import_request = cls(
            file=file,
            fleet=fleet,
            format_=format_,
            options=options,
            name=name,
            description=description,
            duplicate=duplicate,
        )

        application_import_request.additional_properties = d
        return application_import_request

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
