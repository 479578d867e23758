"""The UMA communication-model advisor and the ROS transport advisor (spec 01 sections 9-10, acceptance 18-23)."""

import json

import pytest

from continuum.engine import InputError
from continuum.engine.device import uma_advisor as uma
from continuum.engine.device.ros_transport import ros_overhead, ros_transport_advice, table


def test_device_registry_is_seeded():
    assert [d.id for d in uma.devices()] == ["jetson-nano", "jetson-tx2", "jetson-agx-xavier"]
    xavier = uma.device("jetson-agx-xavier")
    assert xavier.io_coherent and (xavier.gpu_threshold_low_pct, xavier.gpu_threshold_high_pct) == (16.2, 57.1)
    tx2 = uma.device("jetson-tx2")
    assert not tx2.io_coherent and tx2.zc_sc_max_speedup == 70 and not tx2.zc_sc_max_speedup_verified
    assert tx2.peak_ll_l1_gbps == {"sc": 104.15, "um": 97.34, "zc": 1.28}
    assert uma.device(xavier.to_dict()) == xavier
    with pytest.raises(InputError, match="unknown device 'jetson-orin'"):
        uma.device("jetson-orin")
    with pytest.raises(InputError, match="cpu_threshold_pct must be a percentage"):
        uma.device({**xavier.to_dict(), "cpu_threshold_pct": 300})


def test_eq_3_8_and_3_9():
    assert uma.cpu_usage(0.4, 0.5) == pytest.approx(20.0)
    # 1e6 transactions of 32 bytes, half served by L1, in 1 ms: 16 GB/s of the Xavier's 231.14 GB/s SC peak
    assert uma.gpu_usage(1e6, 32, 0.5, 1e-3, 231.14) == pytest.approx(100 * 16 / 231.14)
    with pytest.raises(InputError, match="miss_rate_l1 must be a rate"):
        uma.cpu_usage(1.4, 0.5)


SHWFS = {
    "jetson-nano": {"cpu_usage": 19.8, "gpu_usage": 1.7, "kernel_time": 453.5, "copy_time": 44.8},
    "jetson-tx2": {"cpu_usage": 19.8, "gpu_usage": 3.7, "kernel_time": 175.2, "copy_time": 22.4},
    "jetson-agx-xavier": {"cpu_usage": 6.1, "gpu_usage": 7.0, "kernel_time": 41.24, "copy_time": 16.88},
}
ORB = {
    "jetson-tx2": {"cpu_usage": 0.0, "gpu_usage": 25.3, "kernel_time": 93.56, "copy_time": 1.57},
    "jetson-agx-xavier": {"cpu_usage": 0.0, "gpu_usage": 20.1, "kernel_time": 24.22, "copy_time": 1.35},
}


@pytest.mark.parametrize(
    ("dev", "profile", "recommendation", "zone", "cpu_dependent", "estimate"),
    [
        ("jetson-nano", SHWFS["jetson-nano"], "SC/UM", 1, True, None),  # CPU-dependent, not I/O coherent
        ("jetson-tx2", SHWFS["jetson-tx2"], "SC/UM", 3, True, None),  # both dependent
        ("jetson-agx-xavier", SHWFS["jetson-agx-xavier"], "ZC", 1, False, 1.693),  # Table 4.6: 69.3 %
        ("jetson-tx2", ORB["jetson-tx2"], "SC/UM", 3, False, None),  # Table 4.8
        ("jetson-agx-xavier", ORB["jetson-agx-xavier"], "ZC_CONDITIONAL", 2, False, 1.059),  # 5.9 %
    ],
)
def test_validation_cases_tables_4_6_and_4_8(dev, profile, recommendation, zone, cpu_dependent, estimate):
    out = uma.advise(dev, {**profile, "current_model": "SC"})
    assert out["recommendation"] == recommendation
    assert out["gpu_zone"] == zone and out["cpu_dependent"] is cpu_dependent
    if estimate is None:
        assert out["change"] is False and out["estimated_speedup"] is None
    else:
        assert out["change"] is True and round(out["estimated_speedup"], 3) == estimate
        assert out["tiled_pattern"] is True


def test_zc_to_sc_estimate_and_overlap_term():
    out = uma.advise("jetson-tx2", {"cpu_usage": 30, "gpu_usage": 40, "current_model": "ZC",
                                    "kernel_time": 244.17, "copy_time": 22.4})  # fmt: skip
    assert out["recommendation"] == "SC/UM" and out["change"]
    lower, upper = out["estimated_speedup"], out["estimated_speedup_upper"]
    assert lower == pytest.approx(244.17 / (244.17 + 22.4)) and lower < 1 < upper
    # Eq. 3.10's overlap: r = min/max, so CPU 10 and GPU 40 give (SC - copy) / 1.25
    assert uma.estimate_sc_to_zc(100, 20, cpu_time=10, gpu_time=40) == pytest.approx(100 / (80 / 1.25))
    assert uma.estimate_sc_to_zc(100, 20, cpu_time=40, gpu_time=10) == pytest.approx(100 / (80 / 1.25))
    assert uma.estimate_sc_to_zc(100, 90, cap=2.52) == 2.52
    with pytest.raises(InputError, match="copy_time < sc_runtime"):
        uma.estimate_sc_to_zc(10, 12)


def test_profile_from_counters():
    out = uma.advise(
        "jetson-agx-xavier",
        {"miss_rate_l1": 0.4, "miss_rate_ll": 0.5, "transactions": 1e6, "transaction_bytes": 32,
         "hit_rate_l1": 0.5, "kernel_runtime_s": 1e-3},
    )  # fmt: skip
    assert out["cpu_usage"] == pytest.approx(20) and out["gpu_usage"] == pytest.approx(100 * 16 / 231.14)
    assert out["recommendation"] == "ZC"  # zone 1, and Xavier keeps the CPU cache under ZC
    with pytest.raises(InputError, match="profile needs gpu_usage"):
        uma.advise("jetson-nano", {"cpu_usage": 1, "transactions": 1})
    with pytest.raises(InputError, match="unknown CUDA model 'XC'"):
        uma.advise("jetson-nano", {"cpu_usage": 1, "gpu_usage": 1, "current_model": "XC"})


TABLE_4_7 = [  # (reference, new, published %)
    (1070.1, 1021.5, 5),
    (453.54, 454.92, 0),
    (1070.1, 1796.1, -67),
    (453.54, 467.21, -3),  # Nano
    (765.04, 783.67, -2),
    (175.18, 177.16, -1),
    (765.04, 801.24, -5),
    (175.18, 244.17, -39),  # TX2
    (304.57, 305.80, 0),
    (41.24, 47.08, -14),
    (304.57, 220.15, 38),
    (41.24, 47.14, -14),  # Xavier
]


@pytest.mark.parametrize(("reference", "new", "published"), TABLE_4_7)
def test_table_4_7_speedup_convention(reference, new, published):
    assert abs(uma.speedup_pct(reference, new) - published) <= 1.0


def test_tables_4_11_to_4_14_overheads():
    doc = table()
    checked = 0
    for row in doc["rows"]:
        for board, by_bench in row["ms"].items():
            for bench, ms in by_bench.items():
                if f"{board}.{bench}" in row.get("flagged", {}):
                    assert abs(ros_overhead(ms, doc["reference_ms"][board][bench][row["cuda"]]) - 83) < 1
                    continue
                ref = doc["reference_ms"][board][bench][row["cuda"]]
                assert abs(ros_overhead(ms, ref) - row["overhead_pct"][board][bench]) <= 1.5, (row, board, bench)
                checked += 1
    assert checked == 14 * 4 - 1


def test_tiled_zero_copy_pattern():
    k = 3
    sim = uma.tiled_zc(tiles=9, phases=2 * k, t_cpu_tile=1.0, t_gpu_tile=0.5, t_barrier=0.1)
    for phase in sim["phases"]:
        assert not set(phase["cpu"]) & set(phase["gpu"])  # no tile touched by both sides in one phase
        assert sorted(phase["cpu"] + phase["gpu"]) == list(range(9))
    assert sim["cpu_count"] == [k] * 9 and sim["gpu_count"] == [k] * 9
    # even phases: CPU 5 tiles (5.0) vs GPU 4 (2.0); odd: CPU 4 (4.0) vs GPU 5 (2.5); plus barriers
    assert sim["time"] == pytest.approx(k * (5.0 + 4.0) + 2 * k * 0.1)


def test_threshold_extraction_from_a_microbenchmark_csv():
    csv_text = "\n".join(
        [
            "fraction,sc_throughput,zc_throughput,sc_runtime,zc_runtime",
            "1/16000,2.5,2.45,10,10.2",
            "1/8000,2.8,2.7,10,10.4",
            "1/4000,5.0,3.0,10,16",
            "1/2000,9.0,3.2,10,28",
            "1/1000,20.0,4.0,10,50",
        ]
    )
    out = uma.extract_thresholds(csv_text, peak_gbps=104.15)
    assert out["gpu_threshold_low_fraction"] == pytest.approx(1 / 8000)
    assert out["gpu_threshold_low_pct"] == pytest.approx(100 * 2.8 / 104.15)
    assert out["gpu_threshold_high_fraction"] == pytest.approx(1 / 2000)  # 28/10 - 1 <= 2 < 50/10 - 1
    assert out["gpu_threshold_high_pct"] == pytest.approx(100 * 9.0 / 104.15)
    with pytest.raises(InputError, match="lacks column 'zc_throughput'"):
        uma.extract_thresholds("fraction,sc_throughput\n1,2\n")
    with pytest.raises(InputError, match="line 3: a value is not a number"):
        uma.extract_thresholds("fraction,sc_throughput,zc_throughput\n1/2,1,1\nx,1,1\n")


def test_ros_advisor_rules():
    co_located = ros_transport_advice(0, 1)
    assert (co_located["transport"], co_located["ros_type"], co_located["architecture"]) == (
        "ROS-SHM-ZC",
        "topic",
        "A4",
    )
    assert co_located["data_instances"] == 1 and co_located["topics"] == 2
    assert ros_transport_advice(0, 1, cuda_model="ZC")["architecture"] == "A5"
    remote = ros_transport_advice(1, 1, off_board=True, board="jetson-tx2")
    assert remote["transport"] == "ROS-SC" and remote["architecture"] == "M1"
    assert remote["expected_overhead"]["overhead_pct"] == {"tx2": {"cache": 660, "concurrent": 683}}
    many = ros_transport_advice(2, 2, single_process=True, board="xavier")
    assert (many["transport"], many["architecture"], many["topics"]) == ("ROS-SHM-ZC", "M3", 5)
    assert many["expected_overhead"]["overhead_pct"] == {"xavier": {"cache": 137, "concurrent": 100}}
    (native,) = many["alternatives"]
    assert native["transport"] == "ROS-ZC" and native["data_instances"] == 3  # N + M - 1
    assert many["data_instances_by_transport"] == {"ROS-SC": 7, "ROS-ZC": 3, "ROS-SHM-ZC": 1}
    assert ros_transport_advice(1, 1)["architecture"] == "M3"  # N + M >= 2
    assert ros_transport_advice(0, 1, single_process=True)["alternatives"][0]["architecture"] == "A3"
    assert all(a["transport"] != "service" for a in [co_located, remote, many])
    json.dumps(many)
    with pytest.raises(InputError, match="at least one CPU or GPU worker"):
        ros_transport_advice(0, 0)
    with pytest.raises(InputError, match="no ROS measurements for board 'orin'"):
        ros_transport_advice(1, 0, board="orin")
