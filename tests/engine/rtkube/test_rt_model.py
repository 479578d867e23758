"""RT task model, contracts and the RealTime resource of Listing 3.33 (thesis 2.4, 3.4)."""

import json
from dataclasses import replace
from pathlib import Path

import pytest
import yaml

from continuum.engine import InputError
from continuum.engine.rtkube.rt_model import (
    RT_TAINT,
    RT_TOLERATION,
    RTContainer,
    Taint,
    Toleration,
    cluster_from_dict,
    cluster_to_dict,
    deployment_manifest,
    realtime_from_yaml,
    realtime_resource,
    realtime_to_yaml,
    rtset_from_dict,
    rtset_to_dict,
    untolerated,
)

DATA = Path(__file__).resolve().parents[2] / "data"


def rt(name="x", **kw):
    doc = {"name": name, "criticality": "A", "period": 100, "deadline": 100, "wcet": {"n1": 10}}
    doc.update(kw)
    return doc


def test_listing_3_33_parses_and_gives_its_utilizations():
    [c] = realtime_from_yaml((DATA / "listing_3_33.yaml").read_text())
    assert (c.name, c.criticality, c.period, c.deadline) == ("example-realtime-data", "C", 100, 100)
    assert dict(c.wcet) == {"nodeA": 50, "nodeB": 60}
    assert c.utilization("nodeA") == 0.5 and c.utilization("nodeB") == 0.6
    assert c.utilization("nodeC") is None


def test_realtime_yaml_round_trip_is_the_listing_text():
    text = (DATA / "listing_3_33.yaml").read_text()
    containers = realtime_from_yaml(text)
    dumped = realtime_to_yaml(containers)
    # The first 13 lines of Listing 3.33, field for field and in the listing's order.
    assert dumped == text.split("---\n")[0]
    assert realtime_from_yaml(dumped) == containers


def test_realtime_resource_field_names():
    c = rtset_from_dict({"containers": [rt(wcet={"a": 2.5, "b": 3})]})[0]
    doc = realtime_resource(c, namespace="robots")
    assert doc["apiVersion"] == "rt.scheduling/v1" and doc["kind"] == "RealTime"
    assert doc["metadata"] == {"name": "x", "namespace": "robots"}
    assert doc["spec"] == {
        "criticality": "A",
        "rtPeriod": 100,
        "rtDeadline": 100,
        "rtWcets": [{"node": "a", "rtWcet": 2.5}, {"node": "b", "rtWcet": 3}],
    }


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        ({"criticality": "D"}, "requires ASIL-D capable platform"),
        ({"criticality": "E"}, "unsupported criticality"),
        ({"rtDeadline": 120}, "deadline 120 exceeds period 100"),
        ({"rtWcets": [{"node": "nodeA", "rtWcet": 101}]}, "wcet 101 on node 'nodeA' exceeds deadline 100"),
        ({"rtWcets": []}, "rtWcets needs at least one entry"),
        ({"rtWcets": [{"node": "a", "rtWcet": 1}, {"node": "a", "rtWcet": 2}]}, "node 'a' appears twice"),
        ({"rtPeriod": 0}, "period must be positive"),
        ({"rtPeriod": "100ms"}, "period must be a finite number"),
    ],
)
def test_bad_realtime_resources_are_rejected_by_name(spec, message):
    doc = yaml.safe_load((DATA / "listing_3_33.yaml").read_text().split("---\n")[0])
    doc["spec"].update(spec)
    with pytest.raises(InputError, match=message) as err:
        realtime_from_yaml(yaml.safe_dump(doc))
    assert "RealTime 'example-realtime-data'" in str(err.value)


def test_missing_spec_field_and_malformed_yaml():
    with pytest.raises(InputError, match=r"spec\.rtPeriod is required"):
        realtime_from_yaml(
            "apiVersion: rt.scheduling/v1\nkind: RealTime\nmetadata: {name: a}\nspec: {criticality: A}\n"
        )
    with pytest.raises(InputError, match="malformed YAML at line"):
        realtime_from_yaml("kind: RealTime\n  bad: [\n")
    with pytest.raises(InputError, match="no RealTime document"):
        realtime_from_yaml("kind: Deployment\n")


def test_rtset_contract_reads_and_round_trips():
    doc = json.loads((DATA / "rtkube.rtset.json").read_text())
    cluster = cluster_from_dict(json.loads((DATA / "rtkube.cluster.json").read_text()))
    containers = rtset_from_dict(doc, [n.name for n in cluster])
    by = {c.name: c for c in containers}
    assert by["arm-driver"].criticality == "C" and by["arm-driver"].deadline == 8.0
    assert by["slam-mapper"].utilization("server") == 0.25 and by["slam-mapper"].stateless
    assert not by["dashboard"].is_rt and by["dashboard"].tolerations == ()
    assert by["lidar-driver"].tolerations == (RT_TOLERATION,)
    assert [c.arrival for c in containers] == [0, 1, 2, 3, 4]
    assert rtset_from_dict(rtset_to_dict(containers)) == containers


@pytest.mark.parametrize(
    ("change", "message", "field"),
    [
        ({"period": -5}, "container 'x': period must be positive", "period"),
        ({"deadline": 0}, "container 'x': deadline must be positive", "deadline"),
        ({"wcet": {"n1": 0}}, "container 'x': wcet on node 'n1' must be positive", "wcet"),
        ({"wcet": {"n1": 120}, "deadline": 100}, "wcet 120 on node 'n1' exceeds deadline 100", "wcet"),
        ({"deadline": 150}, "deadline 150 exceeds period 100", "deadline"),
        ({"wcet": {}}, "wcet must map at least one node", "wcet"),
        ({"wcet": {"ghost": 5}}, "wcet names unknown node 'ghost'", "wcet"),
        ({"criticality": "D"}, "criticality D requires ASIL-D capable platform", "criticality"),
        ({"cpu": 0}, "container 'x': cpu must be positive", "cpu"),
        ({"memory_mib": -1}, "container 'x': memory_mib must be positive", "memory_mib"),
        ({"stateless": "yes"}, "stateless must be true or false", "stateless"),
        ({"period": True}, "period must be a finite number", "period"),
    ],
)
def test_rtset_validation_names_container_and_field(change, message, field):
    with pytest.raises(InputError, match=message) as err:
        rtset_from_dict({"format": "continuum.rtset/v1", "containers": [rt(**change)]}, ["n1"])
    assert err.value.field == field


def test_rtset_structure_errors():
    with pytest.raises(InputError, match=r"format 'x' is not continuum\.rtset/v1"):
        rtset_from_dict({"format": "x", "containers": []})
    with pytest.raises(InputError, match="duplicate name"):
        rtset_from_dict({"containers": [rt(), rt()]})
    with pytest.raises(InputError, match=r"containers\[0\]: name is required"):
        rtset_from_dict({"containers": [{"criticality": "A"}]})


def test_non_rt_container_needs_no_timing():
    [c] = rtset_from_dict({"containers": [{"name": "web", "criticality": None, "cpu": 2}]})
    assert not c.is_rt and c.rank == 0 and c.max_utilization() == 0.0 and c.utilization("n") is None


def test_cluster_nodes_threshold_taints_and_errors():
    nodes = cluster_from_dict(
        {
            "format": "continuum.cluster/v1",
            "nodes": [
                {"name": "j", "cpu": 8, "rt": True, "criticality": "C"},
                {"name": "s", "cpu": 4, "rt": True, "sched_rt_runtime_us": 900000, "taints": []},
                {"name": "r", "cpu": 2, "taints": ["gpu=yes:NoSchedule", {"key": "k", "effect": "NoExecute"}]},
            ],
        }
    )
    j, s, r = nodes
    assert j.rt_threshold == pytest.approx(7.6) and j.taints == (RT_TAINT,) and j.is_c_node
    assert s.rt_threshold == pytest.approx(3.6) and s.taints == ()
    assert r.taints == (Taint("gpu", "yes", "NoSchedule"), Taint("k", "", "NoExecute")) and not r.rt
    assert cluster_from_dict(cluster_to_dict(nodes)) == nodes
    for bad, msg in [
        ({"name": "n", "cpu": 0}, "node 'n' cpu must be a positive number"),
        ({"name": "n", "criticality": "D"}, "requires ASIL-D"),
        ({"name": "n", "taints": ["nocolon"]}, "not key=value:Effect"),
        ({"name": "n", "rt": "yes"}, "rt must be true or false"),
        ({"name": "n", "rt_threshold": -1}, "rt_threshold must be positive"),
    ]:
        with pytest.raises(InputError, match=msg):
            cluster_from_dict({"nodes": [bad]})
    with pytest.raises(InputError, match="duplicate node name 'a'"):
        cluster_from_dict({"nodes": [{"name": "a"}, {"name": "a"}]})  # the one cluster parser's wording


def test_tolerations_follow_kubernetes_rules():
    timed = Taint("rt.monitoring/violation", "true", "NoSchedule", until=10.0)
    taints = [RT_TAINT, Taint("soft", "", "PreferNoSchedule"), timed]
    assert untolerated(taints, [RT_TOLERATION], now=5.0) == [timed]
    assert untolerated(taints, [RT_TOLERATION], now=10.0) == []
    assert untolerated(taints, [Toleration(operator="Exists")], now=0.0) == []
    assert untolerated([RT_TAINT], [Toleration("RealTime", "Equal", "other")]) == [RT_TAINT]
    assert untolerated([RT_TAINT], [Toleration("RealTime", "Exists", effect="NoExecute")]) == [RT_TAINT]


def test_deployment_manifest_links_by_label():
    c = RTContainer("cam", "B", 10, 10, {"n": 1}, stateless=True, cpu=0.5, tolerations=(RT_TOLERATION,))
    dep = deployment_manifest(c, "ros:humble")
    tpl = dep["spec"]["template"]
    assert tpl["metadata"]["labels"]["rt-scheduling"] == "cam"
    assert tpl["metadata"]["labels"]["rt.monitoring/stateless"] == "true"
    assert tpl["spec"]["schedulerName"] == "RT-scheduler"
    toleration = {"key": "RealTime", "operator": "Equal", "value": "RT", "effect": "NoSchedule"}
    assert tpl["spec"]["tolerations"] == [toleration]
    assert tpl["spec"]["containers"][0]["resources"] == {"requests": {"cpu": "500m"}}


def test_realtime_extension_fields_are_written_only_when_set_and_read_back():
    [c] = rtset_from_dict({"containers": [rt(stateless=True, cpu=0.5, memory_mib=128)]})
    spec = realtime_resource(c)["spec"]
    assert (spec["stateless"], spec["cpu"], spec["memoryMib"]) == (True, 0.5, 128)
    assert realtime_from_yaml(realtime_to_yaml([c])) == [replace(c, arrival=0.0)]
    [plain] = rtset_from_dict({"containers": [rt()]})
    assert set(realtime_resource(plain)["spec"]) == {"criticality", "rtPeriod", "rtDeadline", "rtWcets"}
    bad = realtime_resource(c)
    bad["spec"]["cpu"] = -1
    with pytest.raises(InputError, match="RealTime 'x': cpu must be positive"):
        realtime_from_yaml(yaml.safe_dump(bad))
