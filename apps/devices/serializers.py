from django.core.exceptions import ValidationError as DjangoValidationError
from rest_framework import serializers

from apps.tenancy.api import ScopedModelSerializer, ScopedSerializer
from apps.tenancy.bounds import BoundedFileField

from .models import DeviceProfile

MODELS = ("SC", "UM", "ZC")


class DeviceProfileSerializer(ScopedModelSerializer):
    class Meta:
        model = DeviceProfile
        fields = [
            "slug",
            "name",
            "io_coherent",
            "cpu_threshold_pct",
            "gpu_threshold_low_pct",
            "gpu_threshold_high_pct",
            "zc_sc_max_speedup",
            "zc_sc_max_speedup_verified",
            "sc_zc_max_speedup",
            "peak_sc_gbps",
            "peak_um_gbps",
            "peak_zc_gbps",
            "bandwidth_limit_gbps",
            "ros_board",
            "notes",
            "created",
            "updated",
        ]
        read_only_fields = ["created", "updated"]

    def validate(self, attrs):
        # The model's own checks (zone 2 above zone 1, a profile the advisor accepts).
        instance = DeviceProfile(**{**(self._current() or {}), **attrs})
        try:
            instance.clean()
        except DjangoValidationError as exc:
            detail = exc.message_dict if hasattr(exc, "error_dict") else {"non_field_errors": exc.messages}
            raise serializers.ValidationError(detail) from exc
        return attrs

    def _current(self) -> dict | None:
        if self.instance is None:
            return None
        return {f: getattr(self.instance, f) for f in self.Meta.fields if f not in ("created", "updated")}


class AdviceRequestSerializer(ScopedSerializer):
    """An application's profile on this board (Eqs. 3.8-3.9 inputs, runtimes for Eqs. 3.10-3.11) and how its
    ROS nodes share the buffer (thesis 3.1.3)."""

    cpu_usage = serializers.FloatField(required=False, min_value=0, help_text="CPU_usage % (Eq. 3.8), or:")
    miss_rate_l1 = serializers.FloatField(required=False, min_value=0, max_value=1, help_text="CPU L1 miss rate")
    miss_rate_ll = serializers.FloatField(required=False, min_value=0, max_value=1, help_text="CPU LLC miss rate")
    gpu_usage = serializers.FloatField(required=False, min_value=0, help_text="GPU_usage % (Eq. 3.9), or:")
    transactions = serializers.FloatField(required=False, min_value=0, help_text="GPU memory transactions t_n")
    transaction_bytes = serializers.FloatField(required=False, min_value=0, help_text="bytes per transaction")
    hit_rate_l1 = serializers.FloatField(required=False, min_value=0, max_value=1, help_text="GPU L1 hit rate")
    kernel_runtime_s = serializers.FloatField(required=False, min_value=1e-12, help_text="kernel runtime (s)")
    current_model = serializers.ChoiceField(choices=MODELS, default="SC", help_text="the CUDA model used now")
    kernel_time = serializers.FloatField(
        required=False, min_value=1e-12, help_text="SC runtime (ZC runtime when current is ZC), for the estimate"
    )
    copy_time = serializers.FloatField(required=False, min_value=0, help_text="copy time per kernel, same unit")
    cpu_time = serializers.FloatField(required=False, min_value=0, help_text="CPU work, for the CPU/GPU overlap")
    gpu_time = serializers.FloatField(required=False, min_value=0, help_text="GPU work, for the CPU/GPU overlap")
    cpu_workers = serializers.IntegerField(default=1, min_value=0, max_value=64, help_text="ROS CPU nodes (N)")
    gpu_workers = serializers.IntegerField(default=1, min_value=0, max_value=64, help_text="ROS GPU nodes (M)")
    off_board = serializers.BooleanField(default=False, help_text="a communicating node runs off this board")
    single_process = serializers.BooleanField(default=False, help_text="all nodes are threads of one process")

    PROFILE = (
        "cpu_usage",
        "miss_rate_l1",
        "miss_rate_ll",
        "gpu_usage",
        "transactions",
        "transaction_bytes",
        "hit_rate_l1",
        "kernel_runtime_s",
        "current_model",
        "kernel_time",
        "copy_time",
        "cpu_time",
        "gpu_time",
    )
    GPU_COUNTERS = ("transactions", "transaction_bytes", "hit_rate_l1", "kernel_runtime_s")

    def validate(self, attrs):
        device: DeviceProfile = self.context["device"]
        errors = {}
        if "cpu_usage" not in attrs and not ("miss_rate_l1" in attrs and "miss_rate_ll" in attrs):
            errors["cpu_usage"] = ["give cpu_usage, or miss_rate_l1 and miss_rate_ll (Eq. 3.8)"]
        if "gpu_usage" not in attrs:
            missing = [k for k in self.GPU_COUNTERS if k not in attrs]
            if missing:
                errors["gpu_usage"] = [f"give gpu_usage, or {', '.join(self.GPU_COUNTERS)} (Eq. 3.9)"]
            elif device.peak_sc_gbps is None:
                errors["gpu_usage"] = [f"{device.name} has no SC peak throughput for Eq. 3.9: give gpu_usage"]
        if ("kernel_time" in attrs) != ("copy_time" in attrs):
            errors["copy_time" if "kernel_time" in attrs else "kernel_time"] = [
                "the estimate needs both kernel_time and copy_time"
            ]
        elif "kernel_time" in attrs and attrs["current_model"] != "ZC" and attrs["copy_time"] >= attrs["kernel_time"]:
            errors["copy_time"] = ["the copies are part of the SC runtime: copy_time must be below kernel_time"]
        if attrs["cpu_workers"] + attrs["gpu_workers"] == 0:
            errors["cpu_workers"] = ["at least one CPU or GPU node shares the buffer"]
        if errors:
            raise serializers.ValidationError(errors)
        return attrs

    def profile(self) -> dict:
        return {k: self.validated_data[k] for k in self.PROFILE if k in self.validated_data}


class ThresholdsRequestSerializer(ScopedSerializer):
    file = BoundedFileField(help_text="micro-benchmark 2 CSV: fraction, sc_throughput, zc_throughput (GB/s)")
    peak_gbps = serializers.FloatField(
        required=False, min_value=1e-9, help_text="default: the device's SC peak, else the CSV's largest SC value"
    )
