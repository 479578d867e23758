"""The ROS pages in a real browser (Playwright, system Chromium; fixtures of tests/dashboard/test_browser.py):
an operator raises a lidar's rate in the topic table, unpins the lidar drivers in the node table, clusters and
places, and the placement page warns that the drivers left the robot."""

import re

import pytest

from tests.conftest import DATA
from tests.containers.test_pages import make_graph
from tests.dashboard.test_browser import SCREENSHOT, browser, log_in, page  # noqa: F401  (fixtures)

pytestmark = [pytest.mark.browser, pytest.mark.django_db(transaction=True)]

# A robot board of 2 cores and a cloud VM: a 1 kHz x 1 MiB lidar stream needs about 4 cores of middleware.
ROBOT_AND_CLOUD = {
    "name": "robot+cloud",
    "nodes": [
        {"name": "mcb", "arch": "amd64", "cpu": 2, "memory_mib": 8192, "labels": {"zone": "robot"}},
        {"name": "cloud-vm", "arch": "amd64", "cpu": 32, "memory_mib": 65536, "labels": {"zone": "cloud"}},
    ],
}


def follow_job(tab) -> None:
    tab.wait_for_selector("#job-state:has-text('Succeeded')")
    tab.click("#job-result")


def test_edit_a_rate_unpin_drivers_and_see_the_off_robot_warning(page, live_server, operator, fleet, api, settings):  # noqa: F811
    from apps.containers.models import RosGraph

    # The scenario needs the lidars' container to leave the robot, which Listing 3.20's 4 containers give.
    settings.CONTINUUM_ROS_CLUSTERING = "thesis"

    row = make_graph(fleet, (DATA / "autoware_reference_system.json").read_bytes())
    assert api.post("/api/v1/clusters/import/", ROBOT_AND_CLOUD, format="json").status_code == 201
    log_in(page, live_server)
    page.goto(f"{live_server.url}/ros/{row.pk}/")

    # The lidar's topic: 1000 Hz of 1 MiB messages, typed into its row.
    topic = page.locator('tr[data-topic="FrontLidarDriver"]')
    topic.locator("input[name=rate_hz]").fill("1000")
    topic.locator("input[name=msg_bytes]").fill("1048576")
    topic.locator("button:has-text('Save')").click()
    page.wait_for_selector("text=Saved topic FrontLidarDriver.")
    assert page.locator('tr[data-topic="FrontLidarDriver"] input[name=rate_hz]').input_value() == "1000.0"
    # A bad value is refused in the page with its unit, and nothing is stored.
    topic = page.locator('tr[data-topic="FrontLidarDriver"]')
    topic.locator("input[name=rate_hz]").evaluate("e => e.removeAttribute('max')")  # past the browser's check
    topic.locator("input[name=rate_hz]").fill("1e9")
    topic.locator("button:has-text('Save')").click()
    page.wait_for_selector("[role=alert]:has-text('rate_hz: at most 100,000 Hz')")
    assert RosGraph.objects.get(pk=row.pk).graph.topics["FrontLidarDriver"].rates["FrontLidarDriver"] == 1000
    assert page.errors == ["Failed to load resource: the server responded with a status of 400 (Bad Request)"]
    page.errors.clear()  # that 400 was the refusal above

    # Unpin both lidar drivers: the robot board no longer holds them.
    for name in ("FrontLidarDriver", "RearLidarDriver"):
        node = page.locator(f'tr[data-node="{name}"]')
        assert "on robot" in node.locator("td").first.inner_text()
        node.locator("select[name=pin]").select_option("free")
        node.locator("button:has-text('Save')").click()
        page.wait_for_selector(f"text=Saved ROS node {name}.")
        assert "on robot" not in page.locator(f'tr[data-node="{name}"] td').first.inner_text()
    page.locator("#nodes").screenshot(path=str(SCREENSHOT.with_name("continuum-ros-nodes.png")))

    # Cluster into 4 containers, then place them with super-clustering.
    page.fill("#cluster input[name=containers]", "4")
    page.click("#cluster button[type=submit]")
    follow_job(page)
    page.wait_for_url(re.compile(r"/ros/clusterings/\d+/$"))
    page.select_option("#place select[name=cluster]", label="robot+cloud")
    page.check("#place input[name=policy][value=superclustering]")
    assert page.locator("#place input[name=drivers_on_robot]").is_checked()
    page.click("#place button[type=submit]")
    follow_job(page)
    page.wait_for_url(re.compile(r"/ros/placements/\d+/$"))

    warning = page.locator("#placement-warnings")
    warning.wait_for()
    text = warning.inner_text()
    assert "FrontLidarDriver" in text and "RearLidarDriver" in text and "cloud-vm" in text and "off the robot" in text
    lidar_row = page.locator("tr", has=page.locator("strong", has_text="FrontLidarDriver"))
    assert "off robot" in lidar_row.inner_text()
    page.screenshot(path=str(SCREENSHOT.with_name("continuum-ros-placement.png")), full_page=True)
    assert not page.errors
