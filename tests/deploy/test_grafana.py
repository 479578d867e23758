"""The Grafana dashboard in deploy/ loads as a dashboard (the fields Grafana's schema requires, a 24-column grid)
and charts only metrics some Continuum process exposes."""

from __future__ import annotations

import json
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DASHBOARD = ROOT / "deploy" / "grafana" / "continuum-dashboard.json"
PANEL_TYPES = {"timeseries", "stat", "gauge", "table", "bargauge", "text", "row"}


def defined_metrics() -> set[str]:
    """Every ``continuum_*`` metric name the code defines (``f"{PREFIX}_name"`` with its module's PREFIX)."""
    names = set()
    for path in [*ROOT.glob("apps/**/*.py"), *ROOT.glob("continuum/**/*.py")]:
        text = path.read_text()
        prefix = re.search(r'^PREFIX = "([a-z_]+)"', text, re.M)
        base = prefix.group(1) if prefix else "continuum"
        names |= {f"{base}_{m}" for m in re.findall(r'f"\{PREFIX\}_([a-z_]+)"', text)}
    return names


def test_the_dashboard_is_a_valid_grafana_dashboard():
    doc = json.loads(DASHBOARD.read_text())
    assert isinstance(doc["uid"], str) and doc["uid"] and isinstance(doc["title"], str) and doc["title"]
    assert isinstance(doc["schemaVersion"], int) and doc["schemaVersion"] >= 36
    assert {v["name"] for v in doc["templating"]["list"]} == {"datasource"}
    ids = [p["id"] for p in doc["panels"]]
    assert len(ids) == len(set(ids)) and doc["panels"]
    for panel in doc["panels"]:
        assert panel["type"] in PANEL_TYPES and panel["title"]
        grid = panel["gridPos"]
        assert all(isinstance(grid[k], int) for k in ("h", "w", "x", "y"))
        assert grid["x"] + grid["w"] <= 24
        assert panel["targets"] and all(t["refId"] and t["expr"] for t in panel["targets"])


def test_every_charted_metric_is_exposed_by_some_process():
    doc = json.loads(DASHBOARD.read_text())
    defined = defined_metrics()
    for panel in doc["panels"]:
        for target in panel["targets"]:
            for name in re.findall(r"\b(continuum_[a-z_]+)", target["expr"]):
                base = re.sub(r"_(total|bucket|count|sum)$", "", name)
                assert base in defined, f"panel {panel['title']!r} charts {name}, which no process exposes"
