"""CPU + integrated-GPU boards with unified memory, as the communication-model advisor needs them (thesis 3.1.2).

A profile holds the board's micro-benchmark results (spec 01 section 9.6): the CPU cache threshold, the GPU
thresholds of zones 1-2, the maximum ZC->SC and SC->ZC speedups and the peak LL->L1 throughputs. The three
published boards (Jetson Nano, TX2, AGX Xavier) are seeded from ``continuum/engine/device/data/uma_devices.json``;
administrators add their own. Profiles are global (a board is a board in every fleet); fleets read them.
"""

from django.core.exceptions import ValidationError
from django.core.validators import MaxValueValidator, MinValueValidator
from django.db import models

from continuum.engine.core.errors import InputError
from continuum.engine.device import uma_advisor

PERCENT = [MinValueValidator(0.0), MaxValueValidator(100.0)]
POSITIVE = [MinValueValidator(1e-9)]


class DeviceProfile(models.Model):
    class RosBoard(models.TextChoices):
        NONE = "", "none (show both boards' figures)"
        TX2 = "tx2", "Jetson TX2 (Tables 4.11-4.12)"
        XAVIER = "xavier", "Jetson AGX Xavier (Tables 4.13-4.14)"

    slug = models.SlugField(max_length=100, unique=True, help_text="the device id, e.g. jetson-tx2")
    name = models.CharField(max_length=200)
    io_coherent = models.BooleanField(
        default=False, help_text="hardware I/O coherence: the CPU cache stays on under zero copy (Xavier)"
    )
    cpu_threshold_pct = models.FloatField(
        validators=PERCENT, help_text="CPU usage (Eq. 3.8) above which the CPU depends on its cache; 100 = never"
    )
    gpu_threshold_low_pct = models.FloatField(
        validators=PERCENT, help_text="GPU usage (Eq. 3.9) up to which ZC and SC perform alike (zone 1)"
    )
    gpu_threshold_high_pct = models.FloatField(
        null=True,
        blank=True,
        validators=PERCENT,
        help_text="end of zone 2 (a ZC/SC gap under 200 %), when the device has one; empty otherwise",
    )
    zc_sc_max_speedup = models.FloatField(
        null=True, blank=True, validators=POSITIVE, help_text="largest ZC->SC speedup (micro-benchmark 1)"
    )
    zc_sc_max_speedup_verified = models.BooleanField(default=True)
    sc_zc_max_speedup = models.FloatField(
        null=True, blank=True, validators=POSITIVE, help_text="largest SC->ZC speedup (micro-benchmark 3)"
    )
    peak_sc_gbps = models.FloatField(
        null=True, blank=True, validators=POSITIVE, help_text="peak GPU LL->L1 throughput under SC (GB/s), Eq. 3.9"
    )
    peak_um_gbps = models.FloatField(null=True, blank=True, validators=POSITIVE, help_text="the same under UM")
    peak_zc_gbps = models.FloatField(null=True, blank=True, validators=POSITIVE, help_text="the same under ZC")
    bandwidth_limit_gbps = models.FloatField(null=True, blank=True, validators=POSITIVE)
    ros_board = models.CharField(
        max_length=16,
        choices=RosBoard.choices,
        blank=True,
        help_text="whose ROS transport measurements to quote as the expected overhead",
    )
    notes = models.TextField(blank=True)
    created = models.DateTimeField(auto_now_add=True)
    updated = models.DateTimeField(auto_now=True)

    class Meta:
        ordering = ["name"]

    def __str__(self) -> str:
        return self.name

    def clean(self) -> None:
        super().clean()
        low, high = self.gpu_threshold_low_pct, self.gpu_threshold_high_pct
        if low is not None and high is not None and high <= low:
            raise ValidationError(
                {"gpu_threshold_high_pct": f"zone 2 must end above zone 1 (the low threshold, {low:g} %)"}
            )
        if self.cpu_threshold_pct is not None and low is not None:
            try:
                self.to_engine()
            except InputError as exc:
                raise ValidationError(str(exc)) from exc

    def to_engine(self) -> uma_advisor.DeviceProfile:
        """The advisor's view of this board."""
        return uma_advisor.DeviceProfile.from_dict(
            {
                "id": self.slug,
                "name": self.name,
                "io_coherent": self.io_coherent,
                "cpu_threshold_pct": self.cpu_threshold_pct,
                "gpu_threshold_low_pct": self.gpu_threshold_low_pct,
                "gpu_threshold_high_pct": self.gpu_threshold_high_pct,
                "zc_sc_max_speedup": self.zc_sc_max_speedup,
                "zc_sc_max_speedup_verified": self.zc_sc_max_speedup_verified,
                "sc_zc_max_speedup": self.sc_zc_max_speedup,
                "peak_ll_l1_gbps": {"sc": self.peak_sc_gbps, "um": self.peak_um_gbps, "zc": self.peak_zc_gbps},
                "bandwidth_limit_gbps": self.bandwidth_limit_gbps,
                "notes": self.notes,
            }
        )
