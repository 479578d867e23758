"""The device page's advice form: a presentation layer over the API's request contract
(:class:`~apps.devices.serializers.AdviceRequestSerializer`), which validates it."""

from __future__ import annotations

from apps.ui.forms import SerializerForm, contract_field

from .models import DeviceProfile
from .serializers import AdviceRequestSerializer

A = AdviceRequestSerializer


class AdviceForm(SerializerForm):
    """An application's profile on a UMA board (the API's advise request, as a form)."""

    serializer_class = AdviceRequestSerializer
    MODELS = [("SC", "standard copy (SC)"), ("UM", "unified memory (UM)"), ("ZC", "zero copy (ZC)")]

    cpu_usage = contract_field(A, "cpu_usage", label="CPU usage %", help_text="")
    miss_rate_l1 = contract_field(A, "miss_rate_l1", label="CPU L1 miss rate", help_text="")
    miss_rate_ll = contract_field(A, "miss_rate_ll", label="CPU LLC miss rate", help_text="")
    gpu_usage = contract_field(A, "gpu_usage", label="GPU usage %", help_text="")
    transactions = contract_field(A, "transactions", label="GPU memory transactions", help_text="")
    transaction_bytes = contract_field(A, "transaction_bytes", label="bytes per transaction", help_text="")
    hit_rate_l1 = contract_field(A, "hit_rate_l1", label="GPU L1 hit rate", help_text="")
    kernel_runtime_s = contract_field(A, "kernel_runtime_s", label="kernel runtime (s)", help_text="")
    current_model = contract_field(A, "current_model", choices=MODELS, required=True, label="CUDA model now")
    kernel_time = contract_field(A, "kernel_time", label="kernel time", help_text="SC runtime (ZC runtime if on ZC)")
    copy_time = contract_field(A, "copy_time", label="copy time per kernel", help_text="")
    cpu_time = contract_field(A, "cpu_time", label="CPU work time", help_text="")
    gpu_time = contract_field(A, "gpu_time", label="GPU work time", help_text="")
    cpu_workers = contract_field(A, "cpu_workers", required=True, label="CPU nodes (N)", help_text="")
    gpu_workers = contract_field(A, "gpu_workers", required=True, label="GPU nodes (M)", help_text="")
    off_board = contract_field(A, "off_board", label="a node runs off this board", help_text="")
    single_process = contract_field(A, "single_process", label="all nodes in one process", help_text="")

    def __init__(self, *args, device: DeviceProfile, **kwargs):
        super().__init__(*args, **kwargs)
        self.device = device

    def serializer_context(self) -> dict:
        return {"device": self.device}

    def request_data(self) -> dict:
        return {k: v for k, v in self.cleaned_data.items() if v is not None}
