"""The thesis's ABV case studies as simulations (§4.5.1 Fig. 4.22, §4.5.2 Fig. 4.24; spec 03 acceptance 15-16).

Thesis scenario, not a reproduction: the Kairos navigation makespan is a model fitted to the thesis' three points
(115/140/125 ms), the per-monitor CPU was chosen so that the Jetson's threshold keeps the thesis' 51 monitors, and
the synthetic testbench's load profile was read back from Fig. 4.22's timeline. These tests check that the
simulator and the MILP behave on the thesis' scenario; they do not show that the thesis' figures follow from
untuned inputs (``benchmarks/thesis.py`` labels F4.22 and F4.24 ``thesis scenario``).
"""

import pytest

from continuum.engine.core.errors import InputError
from continuum.engine.verification.abv_simulation import (
    Navigation,
    Scenario,
    SimMonitor,
    SimNode,
    SimTopic,
    kairos_scenario,
    scenario,
    simulate,
    synthetic_scenario,
)


@pytest.fixture(scope="module")
def synthetic():
    return simulate(synthetic_scenario())


@pytest.fixture(scope="module")
def kairos():
    return simulate(kairos_scenario(duration_s=50.0))


def at(result, t):
    return next(p for p in result.periods if p.t == t)


def test_makespan_model_goes_through_the_thesis_points():
    nav = Navigation()
    assert nav.makespan(0, False) == pytest.approx(115.0)
    assert nav.makespan(201, False) == pytest.approx(140.0)
    assert nav.makespan(51, True) == pytest.approx(125.0)


def test_synthetic_case_follows_fig_4_22(synthetic):
    # 0-20 s: the edge runs all 50 monitors at 38 % (thesis: "about 38 percent")
    assert at(synthetic, 10.0).monitors == {"edge": 50, "desktop": 0, "server": 0}
    assert at(synthetic, 10.0).verification["edge"] == pytest.approx(38.0)
    # the testbench fills the edge from 20 s: monitors go to the desktop in more than one step, all by 24 s
    steps = [m.t for m in synthetic.migrations if m.source == "edge" and m.target == "desktop"]
    assert min(steps) > 20.0 and len(set(steps)) >= 2
    assert at(synthetic, 24.0).monitors["desktop"] == 50
    # the desktop saturates at 40 s: everything goes to the server in one step
    to_server = {m.t for m in synthetic.migrations if m.source == "desktop" and m.target == "server" and m.t < 60}
    assert len(to_server) == 1 and at(synthetic, 42.0).monitors["server"] == 50
    # 65-87 s: 8 % left on the server, the verification needs more: tolerant monitors drop events and the
    # verification stays within the available CPU (thesis: 7.5 % on average)
    for t in range(66, 87):
        p = at(synthetic, float(t))
        assert p.dropped["server"] > 0
        assert p.verification["server"] <= 100.0 - p.background["server"] + 1e-9
        assert p.allocation["status"] == "overloaded"
    assert at(synthetic, 90.0).dropped["server"] == 0
    # every load ends at 105 s: all the monitors come back to the edge
    assert at(synthetic, 107.0).monitors == {"edge": 50, "desktop": 0, "server": 0}
    # The solve time is the machine's (thesis: 27 ms per period; benchmarks/kairos_monitors.py prints ours);
    # what the run must hold is that every period was solved and timed.
    assert synthetic.summary()["milp_mean_ms"] > 0


def test_kairos_migration_brings_the_makespan_under_the_requirement(kairos):
    nav_start = at(kairos, 10.0)
    assert nav_start.monitors == {"mcb": 0, "jetson": 201, "server": 0}
    assert nav_start.makespan_ms == pytest.approx(140.0)  # thesis: 140 ms with every monitor on the Jetson
    assert at(kairos, 2.0).makespan_ms == pytest.approx(115.0)  # no verification yet
    summary = kairos.summary()
    assert summary["moved_off_navigation_node"] >= 140  # thesis: 150 monitors left the Jetson
    # once the monitors have moved the chain meets its 125 ms requirement in every period
    after = [p for p in kairos.periods if p.t >= 21.0]
    assert all(p.makespan_ms <= 125.0 + 1e-9 for p in after)
    # ... and the nodes respect their thresholds (Jetson 60 %, server 90 %) outside migration spikes
    moved_at = {m.t for m in kairos.migrations}
    for p in after:
        if p.t - 1.0 not in moved_at:
            assert p.cpu["jetson"] <= 60.0 + 1e-6 and p.cpu["server"] <= 90.0 + 1e-6
    # the MCB's arm planning (29 s) pushes it over 40 %: its monitors leave for the server (Fig. 4.24)
    assert any(m.source == "mcb" and m.target == "server" and m.t > 29.0 for m in kairos.migrations)
    assert at(kairos, 45.0).cpu["mcb"] <= 40.0 + 1e-6


def test_kairos_navigation_assertion_fails_only_before_the_migration(kairos):
    # the first leg runs with 201 monitors on the Jetson: the robot heads the wrong way, the
    # F[0,timeout] assertion fails at its deadline; the later legs reach the goal
    assert [v["instance_start"] for v in kairos.violations] == [5000.0]
    assert kairos.legs[0]["reached"] is None
    assert all(leg["reached"] is not None for leg in kairos.legs[1:]) and len(kairos.legs) >= 2


def test_migrations_record_the_moved_events(kairos):
    assert kairos.migrations and all(m.events_moved > 0 for m in kairos.migrations)
    assert all(m.source != m.target for m in kairos.migrations)
    doc = kairos.to_dict()
    assert doc["format"] == "continuum.abvsimulation/v1" and len(doc["periods"]) == 51


def test_unknown_scenario_and_bad_inputs_are_rejected():
    with pytest.raises(InputError, match="unknown scenario 'mars'"):
        scenario("mars")
    bad = Scenario(
        "x",
        [SimNode("a")],
        [SimTopic("/t", "b")],
        [],
        {},
    )
    with pytest.raises(InputError, match="topic '/t': unknown publisher 'b'"):
        simulate(bad)
    bad = Scenario("x", [SimNode("a")], [SimTopic("/t", "a")], [SimMonitor("m", ["/t"], {}, "a")], {})
    with pytest.raises(InputError, match="monitor 'm': no CPU figure for node 'a'"):
        simulate(bad)
