"""The CPU-iGPU communication-model advisor for unified-memory boards (thesis 3.1.2, Eqs. 3.8-3.11, Fig. 3.7).

On a UMA board (Jetson Nano, TX2, AGX Xavier) CPU and integrated GPU share one DRAM, and a CUDA program
can move data with standard copies (SC), unified memory (UM, migrated by the driver and treated as SC:
within +-8 % in the micro-benchmarks) or zero copy (ZC: one pinned buffer, no copies, concurrent access,
but the caches are disabled - both on TX2 and Nano, only the GPU's on the I/O-coherent Xavier). The
advisor profiles how much an application relies on the caches and recommends a model:

    CPU_usage% = miss_rate_L1_CPU * (1 - miss_rate_LL_CPU)                                   (Eq. 3.8)
    GPU_usage% = [t_n * t_size * (1 - hit_rate_L1_GPU) / kernel_runtime] / peak_LL_L1_throughput (Eq. 3.9)

Decision (Fig. 3.7 as spec 01 section 9.3 reconstructs it): the CPU is cache-dependent above the
device's CPU threshold; the GPU is in zone 1 up to its low threshold, zone 2 up to the high one (Xavier
only: a gap under 200 %, ZC may still pay) and zone 3 above (cache-dependent). Zone 3 -> SC/UM; zone 1 ->
ZC unless the CPU is cache-dependent on a device without I/O coherence; zone 2 -> ZC_CONDITIONAL when the
CPU is not dependent and the estimated SC->ZC speedup exceeds 1 [PROPOSAL], else SC/UM.

Estimates (Eqs. 3.10, 3.11): with ``r = min(CPU, GPU) / max(CPU, GPU)`` [PROPOSAL: the thesis' CPU/GPU
overlap term is only valid for CPU <= GPU]
    est_ZC = (SC - copy) / (1 + r),  SC->ZC = SC / est_ZC, capped at the device's SC_ZC maximum  (3.10)
    est_SC = ZC * (1 + r) + copy,    ZC->SC = ZC / est_SC (a lower bound: it has no term for the
    restored caches; the upper bound divides ZC * (1 + r) by the device's ZC_SC maximum)         (3.11)
The thesis' "SC/ZC speedup (up to)" figures use the kernel time as SC runtime, the copy per kernel as
copy time and no overlap (``cpu_time = 0``): 41.24 / (41.24 - 16.88) = 1.693 for SH-WFS on Xavier.

Device profiles are data (``data/uma_devices.json``, Nano/TX2/Xavier as published); the same module
extracts thresholds from micro-benchmark CSVs (spec 01 section 9.6 [PROPOSAL]), simulates the tiled ZC
access pattern of Fig. 3.9 and holds the speedup conventions of Tables 4.6-4.9. The ROS transport advice
of 3.1.3 is :mod:`continuum.engine.device.ros_transport`, re-exported here.
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import asdict, dataclass
from functools import cache
from pathlib import Path
from typing import Any

from continuum.engine.core.errors import InputError
from continuum.engine.device.ros_transport import ros_overhead, ros_transport_advice

__all__ = [
    "DeviceProfile",
    "advise",
    "cpu_usage",
    "device",
    "devices",
    "estimate_sc_to_zc",
    "estimate_zc_to_sc",
    "extract_thresholds",
    "gpu_usage",
    "gpu_zone",
    "ros_overhead",
    "ros_transport_advice",
    "speedup_pct",
    "tiled_zc",
]

DATA = Path(__file__).resolve().parent / "data"
MODELS = ("SC", "UM", "ZC")


@dataclass(frozen=True)
class DeviceProfile:
    id: str
    name: str
    io_coherent: bool
    cpu_threshold_pct: float
    gpu_threshold_low_pct: float
    gpu_threshold_high_pct: float | None = None
    zc_sc_max_speedup: float | None = None
    zc_sc_max_speedup_verified: bool = True
    sc_zc_max_speedup: float | None = None
    peak_ll_l1_gbps: dict[str, float | None] | None = None
    bandwidth_limit_gbps: float | None = None
    notes: str = ""

    @classmethod
    def from_dict(cls, doc: dict[str, Any]) -> DeviceProfile:
        try:
            fields = {k: doc[k] for k in cls.__dataclass_fields__ if k in doc}
            profile = cls(**fields)
        except TypeError as exc:
            raise InputError(f"device profile: {exc}", "device") from exc
        for key in ("cpu_threshold_pct", "gpu_threshold_low_pct"):
            value = getattr(profile, key)
            if not isinstance(value, (int, float)) or not 0 <= value <= 100:
                raise InputError(f"device {profile.id!r}: {key} must be a percentage, not {value!r}", "device")
        return profile

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@cache
def _device_table() -> dict[str, DeviceProfile]:
    doc = json.loads((DATA / "uma_devices.json").read_text())
    return {d["id"]: DeviceProfile.from_dict(d) for d in doc["devices"]}


def devices() -> list[DeviceProfile]:
    """The seeded device profiles (Jetson Nano, TX2, AGX Xavier)."""
    return list(_device_table().values())


def device(profile: str | dict[str, Any] | DeviceProfile) -> DeviceProfile:
    """A device profile by id (``jetson-tx2``...), or from a dict of its fields."""
    if isinstance(profile, DeviceProfile):
        return profile
    if isinstance(profile, dict):
        return DeviceProfile.from_dict(profile)
    table = _device_table()
    if profile not in table:
        raise InputError(f"unknown device {profile!r} (known: {', '.join(table)})", "device")
    return table[profile]


# ---- Eqs. 3.8 and 3.9 --------------------------------------------------------------------------------
def _rate(x: float, what: str) -> float:
    if not isinstance(x, (int, float)) or not 0 <= x <= 1:
        raise InputError(f"{what} must be a rate in [0, 1], not {x!r}", what)
    return float(x)


def cpu_usage(miss_rate_l1: float, miss_rate_ll: float) -> float:
    """Eq. 3.8, in %: the share of CPU requests served by the last-level cache."""
    return 100.0 * _rate(miss_rate_l1, "miss_rate_l1") * (1.0 - _rate(miss_rate_ll, "miss_rate_ll"))


def gpu_usage(
    transactions: float, transaction_bytes: float, hit_rate_l1: float, kernel_runtime_s: float, peak_gbps: float
) -> float:
    """Eq. 3.9, in %: the kernel's LL->L1 throughput over the device's peak (SC peak by default)."""
    if kernel_runtime_s <= 0 or peak_gbps <= 0 or transactions < 0 or transaction_bytes < 0:
        raise InputError("gpu_usage needs positive runtime and peak, non-negative transactions", "profile")
    throughput = transactions * transaction_bytes * (1.0 - _rate(hit_rate_l1, "hit_rate_l1")) / kernel_runtime_s
    return 100.0 * throughput / (peak_gbps * 1e9)


def gpu_zone(usage_pct: float, dev: DeviceProfile) -> int:
    """1: ZC and SC perform alike; 2: a gap under 200 % (Xavier-like devices); 3: GPU cache-dependent."""
    if usage_pct <= dev.gpu_threshold_low_pct:
        return 1
    if dev.gpu_threshold_high_pct is not None and usage_pct <= dev.gpu_threshold_high_pct:
        return 2
    return 3


# ---- Eqs. 3.10 and 3.11 ------------------------------------------------------------------------------
def _overlap_ratio(cpu_time: float, gpu_time: float) -> float:
    hi = max(cpu_time, gpu_time)
    return min(cpu_time, gpu_time) / hi if hi > 0 else 0.0


def estimate_sc_to_zc(
    sc_runtime: float, copy_time: float, cpu_time: float = 0.0, gpu_time: float = 0.0, cap: float | None = None
) -> float:
    """Eq. 3.10: the SC->ZC speedup, capped at ``cap`` (the device's SC_ZC maximum) when known."""
    if sc_runtime <= 0 or copy_time < 0 or copy_time >= sc_runtime:
        raise InputError("need 0 <= copy_time < sc_runtime", "profile")
    est_zc = (sc_runtime - copy_time) / (1.0 + _overlap_ratio(cpu_time, gpu_time))
    speedup = sc_runtime / est_zc
    return min(speedup, cap) if cap else speedup


def estimate_zc_to_sc(
    zc_runtime: float, copy_time: float, cpu_time: float = 0.0, gpu_time: float = 0.0, cap: float | None = None
) -> tuple[float, float | None]:
    """Eq. 3.11: (literal lower bound, upper bound with the device's ZC_SC maximum ``cap``)."""
    if zc_runtime <= 0 or copy_time < 0:
        raise InputError("need zc_runtime > 0 and copy_time >= 0", "profile")
    serial = zc_runtime * (1.0 + _overlap_ratio(cpu_time, gpu_time))
    lower = zc_runtime / (serial + copy_time)
    upper = zc_runtime / (serial / cap + copy_time) if cap else None
    return lower, upper


# ---- the decision flow (Fig. 3.7) --------------------------------------------------------------------
def _model(value: str | None) -> str:
    model = (value or "SC").upper()
    if model not in MODELS:
        raise InputError(f"unknown CUDA model {value!r} (choose from {', '.join(MODELS)})", "current_model")
    return model


def advise(dev: str | dict[str, Any] | DeviceProfile, profile: dict[str, Any]) -> dict[str, Any]:
    """Recommend SC/UM, ZC or ZC_CONDITIONAL for an application ``profile`` on device ``dev``.

    ``profile`` keys: ``cpu_usage`` (%), or ``miss_rate_l1`` and ``miss_rate_ll`` (Eq. 3.8); ``gpu_usage``
    (%), or ``transactions``, ``transaction_bytes``, ``hit_rate_l1``, ``kernel_runtime_s`` (Eq. 3.9 against
    the device's SC peak); ``current_model`` (SC, UM or ZC; default SC); for the estimates ``kernel_time``
    (the SC runtime, or the ZC runtime when the current model is ZC), ``copy_time`` and optionally
    ``cpu_time``/``gpu_time`` for the CPU/GPU overlap.
    """
    d = device(dev)
    if not isinstance(profile, dict):
        raise InputError("the application profile must be an object", "profile")
    cpu = profile.get("cpu_usage")
    if cpu is None:
        if "miss_rate_l1" not in profile or "miss_rate_ll" not in profile:
            raise InputError("profile needs cpu_usage or miss_rate_l1 and miss_rate_ll", "profile")
        cpu = cpu_usage(profile["miss_rate_l1"], profile["miss_rate_ll"])
    gpu = profile.get("gpu_usage")
    if gpu is None:
        peak = (d.peak_ll_l1_gbps or {}).get("sc")
        keys = ("transactions", "transaction_bytes", "hit_rate_l1", "kernel_runtime_s")
        if peak is None or any(k not in profile for k in keys):
            raise InputError(f"profile needs gpu_usage, or {', '.join(keys)} and a device SC peak", "profile")
        gpu = gpu_usage(
            profile["transactions"], profile["transaction_bytes"], profile["hit_rate_l1"], profile["kernel_runtime_s"],
            peak,
        )  # fmt: skip
    for value, what in ((cpu, "cpu_usage"), (gpu, "gpu_usage")):
        if not isinstance(value, (int, float)) or value < 0:
            raise InputError(f"{what} must be a non-negative percentage, not {value!r}", "profile")
    current = _model(profile.get("current_model"))
    cpu_dep = cpu > d.cpu_threshold_pct
    zone = gpu_zone(gpu, d)
    kernel, copy = profile.get("kernel_time"), profile.get("copy_time")
    times = (profile.get("cpu_time", 0.0), profile.get("gpu_time", 0.0))
    est_to_zc = None
    if kernel is not None and copy is not None and current in ("SC", "UM"):
        est_to_zc = estimate_sc_to_zc(kernel, copy, *times, cap=d.sc_zc_max_speedup)
    if zone == 3:
        rec, reason = "SC/UM", "the GPU depends on its cache (above the device's GPU threshold)"
    elif zone == 1:
        if not cpu_dep:
            rec, reason = "ZC", "neither CPU nor GPU depends on the cache: same performance, less energy, no copies"
        elif d.io_coherent:
            rec, reason = "ZC", "the CPU depends on its cache, which I/O coherence keeps on under ZC"
        else:
            rec, reason = "SC/UM", "the CPU depends on its cache, which ZC disables on this device"
    elif not cpu_dep and est_to_zc is not None and est_to_zc > 1:
        rec, reason = "ZC_CONDITIONAL", "GPU in zone 2 (gap under 200 %): removing the copies should still pay"
    else:
        rec, reason = "SC/UM", "GPU in zone 2 without an estimated gain from ZC"
    result: dict[str, Any] = {
        "device": d.id,
        "cpu_usage": cpu,
        "gpu_usage": gpu,
        "cpu_dependent": cpu_dep,
        "gpu_zone": zone,
        "current_model": current,
        "recommendation": rec,
        "reason": reason,
        "change": False,
        "estimated_speedup": None,
        "tiled_pattern": rec.startswith("ZC"),
    }
    if rec == "SC/UM" and current in ("SC", "UM"):
        return result  # cache-dependent and already on SC: no suggestion
    if rec.startswith("ZC") and current == "ZC":
        return result
    result["change"] = True
    if rec.startswith("ZC"):
        result["estimated_speedup"] = est_to_zc
    elif kernel is not None and copy is not None:
        lower, upper = estimate_zc_to_sc(kernel, copy, *times, cap=d.zc_sc_max_speedup)
        result["estimated_speedup"] = lower
        result["estimated_speedup_upper"] = upper
    return result


# ---- conventions of Tables 4.6-4.9 -------------------------------------------------------------------
def speedup_pct(reference: float, new: float) -> float:
    """Table 4.7's convention, in %: ``T_ref/T_new - 1`` when new is faster, else ``-(T_new/T_ref - 1)``."""
    if reference <= 0 or new <= 0:
        raise InputError("times must be positive", "times")
    return 100.0 * (reference / new - 1.0) if new <= reference else -100.0 * (new / reference - 1.0)


# ---- micro-benchmark 2: thresholds from a CSV (spec 01 section 9.6 [PROPOSAL]) -----------------------
def extract_thresholds(
    text: str, *, peak_gbps: float | None = None, comparable: float = 0.10, zone2_gap: float = 2.0
) -> dict[str, Any]:
    """GPU cache thresholds from a micro-benchmark CSV.

    Columns: ``fraction`` (share of the array the kernel touches), ``sc_throughput`` and
    ``zc_throughput`` (GB/s), optionally ``sc_runtime`` and ``zc_runtime``. The low threshold is the SC
    throughput at the last fraction (in increasing order) where ZC stays within ``comparable`` of SC,
    over ``peak_gbps`` (default: the largest SC throughput), scanning up from the smallest fraction until
    the first point that is not comparable; the high threshold is the same at the last
    point where ``ZC runtime / SC runtime - 1 <= zone2_gap`` (throughputs stand in for runtimes when absent),
    reported only when it lies beyond the low one.
    """
    rows = list(csv.DictReader(io.StringIO(text)))
    if not rows:
        raise InputError("the micro-benchmark CSV has no data rows", "csv")
    need = {"fraction", "sc_throughput", "zc_throughput"}
    missing = need - set(rows[0])
    if missing:
        raise InputError(f"the micro-benchmark CSV lacks column {sorted(missing)[0]!r}", "csv")
    points = []
    for i, row in enumerate(rows, 2):
        try:
            frac = _fraction(row["fraction"])
            sc, zc = float(row["sc_throughput"]), float(row["zc_throughput"])
            sc_rt = float(row["sc_runtime"]) if row.get("sc_runtime") else None
            zc_rt = float(row["zc_runtime"]) if row.get("zc_runtime") else None
        except (TypeError, ValueError, ZeroDivisionError):
            raise InputError(f"micro-benchmark CSV line {i}: a value is not a number", "csv") from None
        if sc <= 0 or zc <= 0 or not math.isfinite(sc + zc):
            raise InputError(f"micro-benchmark CSV line {i}: throughputs must be positive", "csv")
        points.append((frac, sc, zc, sc_rt, zc_rt))
    points.sort()
    peak = peak_gbps or max(p[1] for p in points)
    low = high = None
    for frac, sc, zc, _, _ in points:  # the initial run of comparable points
        if abs(zc - sc) / sc > comparable:
            break
        low = (frac, sc)
    for frac, sc, zc, sc_rt, zc_rt in points:  # the initial run within the zone-2 gap
        gap = (zc_rt / sc_rt - 1.0) if sc_rt and zc_rt else (sc / zc - 1.0)
        if gap > zone2_gap:
            break
        high = (frac, sc)
    result: dict[str, Any] = {"points": len(points), "peak_gbps": peak}
    result["gpu_threshold_low_pct"] = 100.0 * low[1] / peak if low else 0.0
    result["gpu_threshold_low_fraction"] = low[0] if low else None
    beyond = high if high is not None and (low is None or high[0] > low[0]) else None
    result["gpu_threshold_high_pct"] = 100.0 * beyond[1] / peak if beyond else None
    result["gpu_threshold_high_fraction"] = beyond[0] if beyond else None
    return result


def _fraction(value: str) -> float:
    value = value.strip()
    if "/" in value:
        num, den = value.split("/", 1)
        return float(num) / float(den)
    return float(value)


# ---- the tiled zero-copy access pattern (Fig. 3.9) ---------------------------------------------------
def tiled_zc(tiles: int, phases: int, t_cpu_tile: float, t_gpu_tile: float, t_barrier: float = 0.0) -> dict[str, Any]:
    """Simulate Fig. 3.9: in even phases the CPU works on the even tiles and the GPU on the odd ones, and
    the roles swap in odd phases; a barrier ends each phase. Returns the per-phase tile sets, how many times
    each side processed each tile, and ``T = phases * (max(T_cpu_half, T_gpu_half) + t_barrier)``."""
    if tiles < 1 or phases < 0:
        raise InputError("need at least one tile and a non-negative number of phases", "tiles")
    even = list(range(0, tiles, 2))
    odd = list(range(1, tiles, 2))
    cpu_count = [0] * tiles
    gpu_count = [0] * tiles
    log = []
    total = 0.0
    for phase in range(phases):
        cpu_tiles, gpu_tiles = (even, odd) if phase % 2 == 0 else (odd, even)
        for t in cpu_tiles:
            cpu_count[t] += 1
        for t in gpu_tiles:
            gpu_count[t] += 1
        total += max(len(cpu_tiles) * t_cpu_tile, len(gpu_tiles) * t_gpu_tile) + t_barrier
        log.append({"phase": phase, "cpu": list(cpu_tiles), "gpu": list(gpu_tiles)})
    return {"phases": log, "cpu_count": cpu_count, "gpu_count": gpu_count, "time": total}
