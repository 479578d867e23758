"""UMA device profiles (seeded, admin-managed) and the communication-model advisor through the API."""

import pytest
from django.core.files.uploadedfile import SimpleUploadedFile
from rest_framework.test import APIClient

from apps.devices.admin import DeviceProfileForm
from apps.devices.models import DeviceProfile
from continuum.engine.device import uma_advisor

pytestmark = pytest.mark.django_db

SHWFS = {  # thesis Table 4.6
    "jetson-nano": {"cpu_usage": 19.8, "gpu_usage": 1.7, "kernel_time": 453.5, "copy_time": 44.8},
    "jetson-tx2": {"cpu_usage": 19.8, "gpu_usage": 3.7, "kernel_time": 175.2, "copy_time": 22.4},
    "jetson-agx-xavier": {"cpu_usage": 6.1, "gpu_usage": 7.0, "kernel_time": 41.24, "copy_time": 16.88},
}
ORB = {  # thesis Table 4.8
    "jetson-tx2": {"cpu_usage": 0.0, "gpu_usage": 25.3, "kernel_time": 93.56, "copy_time": 1.57},
    "jetson-agx-xavier": {"cpu_usage": 0.0, "gpu_usage": 20.1, "kernel_time": 24.22, "copy_time": 1.35},
}
MICROBENCH = "fraction,sc_throughput,zc_throughput\n1/16000,2.0,2.0\n1/8000,4.0,3.9\n1/4000,8.0,5.0\n1/2,100.0,1.0\n"


def advise(client, slug, **body):
    return client.post(f"/api/v1/devices/{slug}/advise/", body, format="json")


def test_the_published_boards_are_seeded_by_the_migration(api):
    listed = api.get("/api/v1/devices/").data
    assert [d["slug"] for d in listed["results"]] == ["jetson-agx-xavier", "jetson-nano", "jetson-tx2"]
    for profile in uma_advisor.devices():  # the rows are the engine's data, field for field
        assert DeviceProfile.objects.get(slug=profile.id).to_engine() == profile
    tx2 = api.get("/api/v1/devices/jetson-tx2/").data
    assert (tx2["cpu_threshold_pct"], tx2["gpu_threshold_low_pct"], tx2["peak_sc_gbps"]) == (15.6, 2.7, 104.15)
    assert tx2["ros_board"] == "tx2" and DeviceProfile.objects.get(slug="jetson-nano").ros_board == "tx2"


@pytest.mark.parametrize(
    ("slug", "profile", "recommendation", "zone", "estimate"),
    [
        ("jetson-nano", SHWFS["jetson-nano"], "SC/UM", 1, None),
        ("jetson-tx2", SHWFS["jetson-tx2"], "SC/UM", 3, None),
        ("jetson-agx-xavier", SHWFS["jetson-agx-xavier"], "ZC", 1, 1.693),  # "69.3 %"
        ("jetson-tx2", ORB["jetson-tx2"], "SC/UM", 3, None),
        ("jetson-agx-xavier", ORB["jetson-agx-xavier"], "ZC_CONDITIONAL", 2, 1.059),  # "5.9 %"
    ],
)
def test_advisor_reproduces_the_thesis_validation_cases(api, slug, profile, recommendation, zone, estimate):
    response = advise(api, slug, **profile)
    assert response.status_code == 200, response.data
    answer = response.data["advice"]
    assert (answer["recommendation"], answer["gpu_zone"]) == (recommendation, zone)
    if estimate is None:
        assert answer["estimated_speedup"] is None and not answer["change"]
    else:
        assert round(answer["estimated_speedup"], 3) == estimate and answer["tiled_pattern"]
    ros = response.data["ros_transport"]
    # One CPU and one GPU node on the board share the buffer: the scheduler-node SHM-ZC architecture.
    assert (ros["transport"], ros["architecture"], ros["ros_type"]) == ("ROS-SHM-ZC", "M3", "topic")
    assert ros["cuda_model"] == ("ZC" if recommendation.startswith("ZC") else "SC")
    board = "xavier" if slug == "jetson-agx-xavier" else "tx2"
    assert set(ros["expected_overhead"]["overhead_pct"]) == {board}


def test_advisor_from_profiler_counters_and_ros_placement(api):
    # Eq. 3.8: 0.4 * (1 - 0.5) = 20 % > TX2's 15.6 %; Eq. 3.9 against the TX2's SC peak of 104.15 GB/s.
    body = {
        "miss_rate_l1": 0.4,
        "miss_rate_ll": 0.5,
        "transactions": 1e6,
        "transaction_bytes": 32,
        "hit_rate_l1": 0.5,
        "kernel_runtime_s": 1e-3,
        "cpu_workers": 1,
        "gpu_workers": 0,
        "off_board": True,
    }
    answer = advise(api, "jetson-tx2", **body).data
    assert answer["advice"]["cpu_usage"] == pytest.approx(20.0)
    assert answer["advice"]["gpu_usage"] == pytest.approx(100 * 16 / 104.15)
    assert answer["advice"]["cpu_dependent"] is True
    assert (answer["ros_transport"]["transport"], answer["ros_transport"]["architecture"]) == ("ROS-SC", "A1")


def test_zc_to_sc_reports_both_bounds(api):
    body = {"cpu_usage": 30, "gpu_usage": 40, "current_model": "ZC", "kernel_time": 244.17, "copy_time": 22.4}
    answer = advise(api, "jetson-tx2", **body).data["advice"]
    assert answer["recommendation"] == "SC/UM" and answer["change"]
    assert answer["estimated_speedup"] == pytest.approx(244.17 / (244.17 + 22.4))
    assert answer["estimated_speedup_upper"] > 1


@pytest.mark.parametrize(
    ("body", "field"),
    [
        ({"gpu_usage": 3}, "cpu_usage"),
        ({"cpu_usage": 3, "miss_rate_l1": 0.2}, "gpu_usage"),
        ({"cpu_usage": 3, "transactions": 10}, "gpu_usage"),
        ({"cpu_usage": 3, "gpu_usage": 3, "miss_rate_l1": 1.5}, "miss_rate_l1"),
        ({"cpu_usage": -1, "gpu_usage": 3}, "cpu_usage"),
        ({"cpu_usage": 3, "gpu_usage": 3, "kernel_time": 10}, "copy_time"),
        ({"cpu_usage": 3, "gpu_usage": 3, "kernel_time": 10, "copy_time": 12}, "copy_time"),
        ({"cpu_usage": 3, "gpu_usage": 3, "current_model": "DMA"}, "current_model"),
        ({"cpu_usage": 3, "gpu_usage": 3, "cpu_workers": 0, "gpu_workers": 0}, "cpu_workers"),
    ],
)
def test_bad_profiles_answer_400_naming_the_field(api, body, field):
    response = advise(api, "jetson-tx2", **body)
    assert response.status_code == 400 and field in response.data, response.data


def test_nano_has_no_sc_peak_so_counters_cannot_give_gpu_usage(api):
    body = {"cpu_usage": 1, "transactions": 1e6, "transaction_bytes": 32, "hit_rate_l1": 0.5, "kernel_runtime_s": 1}
    response = advise(api, "jetson-nano", **body)
    assert response.status_code == 400 and "no SC peak" in str(response.data["gpu_usage"])


def test_unknown_device_is_404_and_unauthenticated_is_refused(api):
    assert advise(api, "jetson-orin", cpu_usage=1, gpu_usage=1).status_code == 404
    assert APIClient().get("/api/v1/devices/").status_code in (401, 403)
    assert APIClient().post("/api/v1/devices/jetson-tx2/advise/", {}, format="json").status_code in (401, 403)


def test_fleet_tokens_read_but_only_staff_sessions_write(api, client, django_user_model):
    new = {"slug": "orin", "name": "Jetson Orin", "cpu_threshold_pct": 50, "gpu_threshold_low_pct": 10}
    assert api.post("/api/v1/devices/", new, format="json").status_code == 403
    assert api.patch("/api/v1/devices/jetson-tx2/", {"cpu_threshold_pct": 1}, format="json").status_code == 403
    assert api.delete("/api/v1/devices/jetson-tx2/").status_code == 403
    staff = django_user_model.objects.create_user("staff", password="staff-pass-123", is_staff=True)
    client.force_login(staff)
    created = client.post("/api/v1/devices/", new, content_type="application/json")
    assert created.status_code == 201, created.json()
    bad = client.patch(
        "/api/v1/devices/orin/", {"gpu_threshold_high_pct": 5}, content_type="application/json"
    )  # zone 2 must end above zone 1
    assert bad.status_code == 400 and "gpu_threshold_high_pct" in bad.json()
    assert advise(api, "orin", cpu_usage=10, gpu_usage=5).data["advice"]["recommendation"] == "ZC"
    # A board without ROS measurements of its own gets both boards' priors.
    assert set(advise(api, "orin", cpu_usage=10, gpu_usage=5).data["ros_transport"]["expected_overhead"]
               ["overhead_pct"]) == {"tx2", "xavier"}  # fmt: skip


def test_thresholds_from_a_microbenchmark_csv(api):
    response = api.post(
        "/api/v1/devices/jetson-tx2/thresholds/",
        {"file": SimpleUploadedFile("mb.csv", MICROBENCH.encode()), "peak_gbps": 100},
        format="multipart",
    )
    assert response.status_code == 200, response.data
    # Comparable (within 10 %) up to 1/8000, where SC gives 4 GB/s of the 100 GB/s peak.
    assert response.data["gpu_threshold_low_pct"] == pytest.approx(4.0)
    assert response.data["gpu_threshold_low_fraction"] == pytest.approx(1 / 8000)
    assert DeviceProfile.objects.get(slug="jetson-tx2").gpu_threshold_low_pct == 2.7  # nothing changed
    bad = api.post(
        "/api/v1/devices/jetson-tx2/thresholds/",
        {"file": SimpleUploadedFile("mb.csv", b"fraction,sc_throughput\n1/2,3\n")},
        format="multipart",
    )
    assert bad.status_code == 400 and "lacks column 'zc_throughput'" in str(bad.data["file"])


# ---- the admin form ---------------------------------------------------------------------------------------
def form(data, files=None, instance=None):
    base = {"name": "My board", "slug": "my-board", "cpu_threshold_pct": 20, "zc_sc_max_speedup_verified": True}
    return DeviceProfileForm({**base, **data}, files or {}, instance=instance)


def test_admin_form_validates_a_new_board():
    assert form({"gpu_threshold_low_pct": 5, "gpu_threshold_high_pct": 40}).is_valid()
    f = form({"gpu_threshold_low_pct": 5, "gpu_threshold_high_pct": 4})
    assert not f.is_valid() and "zone 2 must end above zone 1" in str(f.errors["gpu_threshold_high_pct"])
    f = form({"gpu_threshold_low_pct": 150})
    assert not f.is_valid() and "gpu_threshold_low_pct" in f.errors
    f = form({})
    assert not f.is_valid() and "micro-benchmark CSV" in str(f.errors["gpu_threshold_low_pct"])
    f = form({"gpu_threshold_low_pct": 5, "sc_zc_max_speedup": 0})
    assert not f.is_valid() and "sc_zc_max_speedup" in f.errors


def test_admin_form_fills_thresholds_from_a_microbenchmark_csv():
    f = form({"peak_sc_gbps": 100}, {"microbenchmark": SimpleUploadedFile("mb.csv", MICROBENCH.encode())})
    assert f.is_valid(), f.errors
    device = f.save()
    assert device.gpu_threshold_low_pct == 4.0
    assert device.gpu_threshold_high_pct == 8.0  # 1/4000: ZC 5 vs SC 8 GB/s is within the 200 % gap
    f = form({}, {"microbenchmark": SimpleUploadedFile("mb.csv", b"fraction,sc_throughput,zc_throughput\n1/2,x,1\n")})
    assert not f.is_valid() and "mb.csv: micro-benchmark CSV line 2" in str(f.errors["microbenchmark"])


def test_admin_pages_for_staff(client, django_user_model):
    admin = django_user_model.objects.create_superuser("root", password="root-pass-123")
    client.force_login(admin)
    assert client.get("/admin/devices/deviceprofile/").status_code == 200
    page = client.get(f"/admin/devices/deviceprofile/{DeviceProfile.objects.get(slug='jetson-tx2').pk}/change/")
    assert page.status_code == 200 and b"Micro-benchmark 2 CSV" in page.content
