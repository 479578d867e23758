"""Administrators manage the board profiles; a micro-benchmark CSV can fill the GPU thresholds."""

from django import forms
from django.contrib import admin

from continuum.engine.core.errors import InputError
from continuum.engine.device.uma_advisor import extract_thresholds

from .models import DeviceProfile


class DeviceProfileForm(forms.ModelForm):
    """The profile's fields (validated by the model and the advisor), plus an optional micro-benchmark CSV."""

    microbenchmark = forms.FileField(
        required=False,
        label="Micro-benchmark 2 CSV",
        help_text=(
            "columns fraction, sc_throughput, zc_throughput (GB/s), optionally sc_runtime, zc_runtime: "
            "fills the GPU thresholds (spec 01 section 9.6), against the SC peak when it is set"
        ),
    )

    class Meta:
        model = DeviceProfile
        fields = "__all__"

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.fields["gpu_threshold_low_pct"].required = False  # a CSV may give it

    def clean(self):
        data = super().clean()
        upload = data.get("microbenchmark")
        if upload is None:
            if data.get("gpu_threshold_low_pct") is None and "gpu_threshold_low_pct" not in self.errors:
                self.add_error("gpu_threshold_low_pct", "give the low GPU threshold or a micro-benchmark CSV")
            return data
        try:
            text = upload.read().decode("utf-8")
            found = extract_thresholds(text, peak_gbps=data.get("peak_sc_gbps"))
        except UnicodeDecodeError:
            self.add_error("microbenchmark", "the file is not UTF-8 text")
            return data
        except InputError as exc:
            self.add_error("microbenchmark", f"{upload.name}: {exc}")
            return data
        # The thresholds from the file replace what the form says; the model's clean() still checks them.
        data["gpu_threshold_low_pct"] = round(found["gpu_threshold_low_pct"], 3)
        high = found["gpu_threshold_high_pct"]
        data["gpu_threshold_high_pct"] = None if high is None else round(high, 3)
        return data


@admin.register(DeviceProfile)
class DeviceProfileAdmin(admin.ModelAdmin):
    form = DeviceProfileForm
    list_display = [
        "name",
        "slug",
        "io_coherent",
        "cpu_threshold_pct",
        "gpu_threshold_low_pct",
        "gpu_threshold_high_pct",
        "zc_sc_max_speedup",
        "sc_zc_max_speedup",
    ]
    search_fields = ["name", "slug"]
    prepopulated_fields = {"slug": ["name"]}
    fieldsets = [
        (None, {"fields": ["name", "slug", "io_coherent", "ros_board", "notes"]}),
        (
            "Cache thresholds (micro-benchmark 2)",
            {"fields": ["cpu_threshold_pct", "gpu_threshold_low_pct", "gpu_threshold_high_pct", "microbenchmark"]},
        ),
        (
            "Speedups and throughputs (micro-benchmarks 1 and 3)",
            {
                "fields": [
                    "zc_sc_max_speedup",
                    "zc_sc_max_speedup_verified",
                    "sc_zc_max_speedup",
                    "peak_sc_gbps",
                    "peak_um_gbps",
                    "peak_zc_gbps",
                    "bandwidth_limit_gbps",
                ]
            },
        ),
    ]
