"""Seed the boards the thesis measured (Jetson Nano, TX2, AGX Xavier) from the engine's uma_devices.json."""

import json
from pathlib import Path

from django.db import migrations

import continuum.engine

SEED = Path(continuum.engine.__file__).resolve().parent / "device" / "data" / "uma_devices.json"
# Whose ROS transport measurements (thesis Tables 4.11-4.14) each board quotes; the Nano has none of its own.
ROS_BOARD = {"jetson-nano": "tx2", "jetson-tx2": "tx2", "jetson-agx-xavier": "xavier"}


def seed(apps, schema_editor):
    DeviceProfile = apps.get_model("devices", "DeviceProfile")
    for doc in json.loads(SEED.read_text())["devices"]:
        peak = doc.get("peak_ll_l1_gbps") or {}
        DeviceProfile.objects.update_or_create(
            slug=doc["id"],
            defaults={
                "name": doc["name"],
                "io_coherent": doc["io_coherent"],
                "cpu_threshold_pct": doc["cpu_threshold_pct"],
                "gpu_threshold_low_pct": doc["gpu_threshold_low_pct"],
                "gpu_threshold_high_pct": doc.get("gpu_threshold_high_pct"),
                "zc_sc_max_speedup": doc.get("zc_sc_max_speedup"),
                "zc_sc_max_speedup_verified": doc.get("zc_sc_max_speedup_verified", True),
                "sc_zc_max_speedup": doc.get("sc_zc_max_speedup"),
                "peak_sc_gbps": peak.get("sc"),
                "peak_um_gbps": peak.get("um"),
                "peak_zc_gbps": peak.get("zc"),
                "bandwidth_limit_gbps": doc.get("bandwidth_limit_gbps"),
                "ros_board": ROS_BOARD.get(doc["id"], ""),
                "notes": doc.get("notes", ""),
            },
        )


def unseed(apps, schema_editor):
    DeviceProfile = apps.get_model("devices", "DeviceProfile")
    DeviceProfile.objects.filter(slug__in=[d["id"] for d in json.loads(SEED.read_text())["devices"]]).delete()


class Migration(migrations.Migration):
    dependencies = [("devices", "0001_initial")]

    operations = [migrations.RunPython(seed, unseed)]
