from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.current_model_enum import CurrentModelEnum, check_current_model_enum
from ..types import UNSET, Unset

T = TypeVar("T", bound="AdviceRequestRequest")


@_attrs_define
class AdviceRequestRequest:
    """An application's profile on this board (Eqs. 3.8-3.9 inputs, runtimes for Eqs. 3.10-3.11) and how its
    ROS nodes share the buffer (thesis 3.1.3).

        Attributes:
            cpu_usage (float | Unset): CPU_usage % (Eq. 3.8), or:
            miss_rate_l1 (float | Unset): CPU L1 miss rate
            miss_rate_ll (float | Unset): CPU LLC miss rate
            gpu_usage (float | Unset): GPU_usage % (Eq. 3.9), or:
            transactions (float | Unset): GPU memory transactions t_n
            transaction_bytes (float | Unset): bytes per transaction
            hit_rate_l1 (float | Unset): GPU L1 hit rate
            kernel_runtime_s (float | Unset): kernel runtime (s)
            current_model (CurrentModelEnum | Unset): * `SC` - SC
                * `UM` - UM
                * `ZC` - ZC Default: 'SC'.
            kernel_time (float | Unset): SC runtime (ZC runtime when current is ZC), for the estimate
            copy_time (float | Unset): copy time per kernel, same unit
            cpu_time (float | Unset): CPU work, for the CPU/GPU overlap
            gpu_time (float | Unset): GPU work, for the CPU/GPU overlap
            cpu_workers (int | Unset): ROS CPU nodes (N) Default: 1.
            gpu_workers (int | Unset): ROS GPU nodes (M) Default: 1.
            off_board (bool | Unset): a communicating node runs off this board Default: False.
            single_process (bool | Unset): all nodes are threads of one process Default: False.
    """

    cpu_usage: float | Unset = UNSET
    miss_rate_l1: float | Unset = UNSET
    miss_rate_ll: float | Unset = UNSET
    gpu_usage: float | Unset = UNSET
    transactions: float | Unset = UNSET
    transaction_bytes: float | Unset = UNSET
    hit_rate_l1: float | Unset = UNSET
    kernel_runtime_s: float | Unset = UNSET
    current_model: CurrentModelEnum | Unset = "SC"
    kernel_time: float | Unset = UNSET
    copy_time: float | Unset = UNSET
    cpu_time: float | Unset = UNSET
    gpu_time: float | Unset = UNSET
    cpu_workers: int | Unset = 1
    gpu_workers: int | Unset = 1
    off_board: bool | Unset = False
    single_process: bool | Unset = False
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        cpu_usage = self.cpu_usage

        miss_rate_l1 = self.miss_rate_l1

        miss_rate_ll = self.miss_rate_ll

        gpu_usage = self.gpu_usage

        transactions = self.transactions

        transaction_bytes = self.transaction_bytes

        hit_rate_l1 = self.hit_rate_l1

        kernel_runtime_s = self.kernel_runtime_s

        current_model: str | Unset = UNSET
        if not isinstance(self.current_model, Unset):
            current_model = self.current_model

        kernel_time = self.kernel_time

        copy_time = self.copy_time

        cpu_time = self.cpu_time

        gpu_time = self.gpu_time

        cpu_workers = self.cpu_workers

        gpu_workers = self.gpu_workers

        off_board = self.off_board

        single_process = self.single_process

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if cpu_usage is not UNSET:
            field_dict["cpu_usage"] = cpu_usage
        if miss_rate_l1 is not UNSET:
            field_dict["miss_rate_l1"] = miss_rate_l1
        if miss_rate_ll is not UNSET:
            field_dict["miss_rate_ll"] = miss_rate_ll
        if gpu_usage is not UNSET:
            field_dict["gpu_usage"] = gpu_usage
        if transactions is not UNSET:
            field_dict["transactions"] = transactions
        if transaction_bytes is not UNSET:
            field_dict["transaction_bytes"] = transaction_bytes
        if hit_rate_l1 is not UNSET:
            field_dict["hit_rate_l1"] = hit_rate_l1
        if kernel_runtime_s is not UNSET:
            field_dict["kernel_runtime_s"] = kernel_runtime_s
        if current_model is not UNSET:
            field_dict["current_model"] = current_model
        if kernel_time is not UNSET:
            field_dict["kernel_time"] = kernel_time
        if copy_time is not UNSET:
            field_dict["copy_time"] = copy_time
        if cpu_time is not UNSET:
            field_dict["cpu_time"] = cpu_time
        if gpu_time is not UNSET:
            field_dict["gpu_time"] = gpu_time
        if cpu_workers is not UNSET:
            field_dict["cpu_workers"] = cpu_workers
        if gpu_workers is not UNSET:
            field_dict["gpu_workers"] = gpu_workers
        if off_board is not UNSET:
            field_dict["off_board"] = off_board
        if single_process is not UNSET:
            field_dict["single_process"] = single_process

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        cpu_usage = d.pop("cpu_usage", UNSET)

        miss_rate_l1 = d.pop("miss_rate_l1", UNSET)

        miss_rate_ll = d.pop("miss_rate_ll", UNSET)

        gpu_usage = d.pop("gpu_usage", UNSET)

        transactions = d.pop("transactions", UNSET)

        transaction_bytes = d.pop("transaction_bytes", UNSET)

        hit_rate_l1 = d.pop("hit_rate_l1", UNSET)

        kernel_runtime_s = d.pop("kernel_runtime_s", UNSET)

        _current_model = d.pop("current_model", UNSET)
        current_model: CurrentModelEnum | Unset
        current_model = UNSET if isinstance(_current_model, Unset) else check_current_model_enum(_current_model)

        kernel_time = d.pop("kernel_time", UNSET)

        copy_time = d.pop("copy_time", UNSET)

        cpu_time = d.pop("cpu_time", UNSET)

        gpu_time = d.pop("gpu_time", UNSET)

        cpu_workers = d.pop("cpu_workers", UNSET)

        gpu_workers = d.pop("gpu_workers", UNSET)

        off_board = d.pop("off_board", UNSET)

        single_process = d.pop("single_process", UNSET)

        advice_request_request = cls(
            cpu_usage=cpu_usage,
            miss_rate_l1=miss_rate_l1,
            miss_rate_ll=miss_rate_ll,
            gpu_usage=gpu_usage,
            transactions=transactions,
            transaction_bytes=transaction_bytes,
            hit_rate_l1=hit_rate_l1,
            kernel_runtime_s=kernel_runtime_s,
            current_model=current_model,
            kernel_time=kernel_time,
            copy_time=copy_time,
            cpu_time=cpu_time,
            gpu_time=gpu_time,
            cpu_workers=cpu_workers,
            gpu_workers=gpu_workers,
            off_board=off_board,
            single_process=single_process,
        )

        advice_request_request.additional_properties = d
        return advice_request_request

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
