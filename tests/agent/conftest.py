"""The node agent's tests reuse the RT-Kube app's RT cluster (node0/node1: A/B nodes, node2: C, node3: no RT)."""

import pytest

from tests.realtime.conftest import rt_cluster  # noqa: F401


@pytest.fixture
def server(live_server, fleet_token, api, rt_cluster):  # noqa: F811 (the fixture imported above)
    """The live server, the fleet's token and a helper that creates a RealTime object through the API."""

    def realtime(name, period, deadline, wcet, node="node0"):
        body = {"cluster": rt_cluster.pk, "name": name, "criticality": "A", "period": period, "deadline": deadline,
                "wcets": [{"node": node, "wcet": wcet}], "stateless": True}  # fmt: skip
        response = api.post("/api/v1/realtimes/", body, format="json")
        assert response.status_code == 201, response.data
        return response.data

    return {"url": live_server.url, "token": fleet_token.plaintext, "realtime": realtime, "api": api,
            "cluster": rt_cluster}  # fmt: skip
