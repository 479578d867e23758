"""Every path of the monitor follows one sample-and-hold rule for placeholder bits, and offline checking
decides the windows that close at the trace's last instant.

Propositions that read no signal (``5 > 0``, ``{true}``, one that constants made constant) and braced
propositions that are true while their signal is unseen (``{!(y > 5)}``) are the cases where a monitor that
starts its bits at False, instead of computing them from the (empty) held values, gives wrong verdicts.
Every monitor here is compared with the oracle (tests/engine/stl_oracle.py), which evaluates propositions
on the held values of each instant and shares none of the monitor's machinery, online, after a JSON
restore, across migrations and after resets.
"""

import json
import random

import pytest

from continuum.engine.verification.stl_monitor import Monitor, check_trace, synthesize
from continuum.engine.verification.stl_parser import parse_assertion

from .stl_oracle import instance_verdicts
from .test_stl_migration import Network, _stream
from .test_stl_monitor import _monitor_instances, _random_events

CONSTANTS = {"LIM": 3.0}

# (assertion, trace, expected verdict online): each reads at least one proposition whose bit is not False
# before the signals it reads (if any) are seen
CASES = [
    ("G(5 > 0)", [("x", 1, 0), ("x", 2, 1)], "pass"),
    ("G({true})", [("x", 1, 0)], "pass"),
    ("G(1 < 2)", [("y", 0, 0), ("y", 0, 4)], "pass"),
    ("G(LIM > 2)", [("x", 1, 0), ("x", 9, 3)], "pass"),  # constant after substitution
    ("G(LIM < 2)", [("x", 1, 0)], "fail"),
    ("G({!(y > 5)})", [("x", 1, 0), ("x", 2, 1), ("y", 3, 2)], "pass"),  # y unseen at 0 and 1: true
    ("G({!(y > 5)})", [("x", 1, 0), ("y", 7, 2)], "fail"),
    ("G(x > 0 -> {!(y > 5)})", [("x", 1, 0), ("x", 2, 5), ("y", 1, 6)], "pass"),
    ("G(x > 0 -> F[0,2]({!(y > 5)}))", [("x", 1, 0), ("x", 2, 1), ("y", 9, 2), ("x", 0, 2)], "pass"),  # fast path
    ("G({!(y > 5)} -> F[0,1](x > 3))", [("x", 1, 0), ("x", 1, 4)], "fail"),  # fast path, antecedent true
    ("G(1 < 2 -> F[1,3](x > 3))", [("x", 1, 0), ("x", 5, 2)], "inconclusive"),  # the instance at 2 waits
    ("G((1 < 2) U[0,3] (x > 3))", [("x", 1, 0), ("x", 5, 2)], "pass"),
    ("G(X({true}))", [("x", 1, 0), ("x", 1, 1)], "inconclusive"),
]


def _online(text, events, **options):
    m = Monitor(synthesize(text, CONSTANTS), **options)
    got = []
    for e in events:  # one event at a time: the handler's online path
        got += m.feed([e])
    got += m.flush()
    return m, got


def _assert_matches_oracle(text, events, monitor, violations, mode="timestamp"):
    expected = instance_verdicts(parse_assertion(text, CONSTANTS), events, mode)
    got = _monitor_instances(monitor.result(violations), set(monitor.pending_starts()), expected)
    for ts, want in expected.items():
        if want is not None:
            assert got[ts] == want, (text, events, ts)
    want_verdict = "fail" if False in got.values() else "inconclusive" if None in got.values() else "pass"
    assert monitor.verdict() == want_verdict, (text, events)


@pytest.mark.parametrize(("text", "events", "verdict"), CASES)
@pytest.mark.parametrize("fast", [True, False])
def test_signal_free_and_unseen_signal_propositions_online(text, events, verdict, fast):
    m, got = _online(text, events, fast_path=fast)
    assert m.verdict() == verdict, (text, [v.to_dict() for v in got])
    _assert_matches_oracle(text, events, m, got)


@pytest.mark.parametrize(("text", "events", "verdict"), CASES)
def test_fresh_and_restored_monitors_hold_the_same_bits(text, events, verdict):
    program = synthesize(text, CONSTANTS)
    fresh = Monitor(program)
    restored = Monitor.from_dict(json.loads(json.dumps(fresh.to_dict())))
    assert fresh.bits == restored.bits
    got = restored.feed(events) + restored.flush()
    assert restored.verdict() == verdict
    _assert_matches_oracle(text, events, restored, got)


def test_bits_before_any_event_are_those_of_the_empty_held_state():
    m = Monitor(synthesize("G(x > 0 -> {!(y > 5)} && 1 < 2 && {true} && LIM > 2 && y > 5)", CONSTANTS))
    assert dict(zip([p.text for p in m.program.placeholders], m.bits, strict=True)) == {
        "x > 0": False,
        "{!y > 5}": True,
        "1 < 2": True,
        "{true}": True,
        "3 > 2": True,
        "y > 5": False,
    }


# atoms whose bit does not start False, mixed with ordinary ones
ATOMS = ["5 > 0", "{true}", "LIM >= 3", "LIM < 1", "{!(y > 5)}", "{!a}", "x > 3", "a", "{!(x >= 2) && !b}"]


def _formula(rng, depth):
    if depth == 0:
        return rng.choice(ATOMS)
    sub = lambda: _formula(rng, depth - 1)  # noqa: E731
    lo = rng.randrange(4)
    hi = lo + rng.randrange(4)
    return rng.choice(
        [
            lambda: f"!{sub()}",
            lambda: f"({sub()} && {sub()})",
            lambda: f"({sub()} || {sub()})",
            lambda: f"F[{lo},{hi}]({sub()})",
            lambda: f"X({sub()})",
            lambda: f"(({sub()}) U[{lo},{hi}] ({sub()}))",
            lambda: f"(({sub()}) R[{lo},{hi}] ({sub()}))",
        ]
    )()


def _texts(rng, n):
    out = []
    for _ in range(n):
        out.append(f"G({_formula(rng, rng.randint(0, 2))} -> {_formula(rng, rng.randint(0, 2))})")
    return out


def test_random_signal_free_formulas_match_the_oracle_online_and_after_restore():
    rng = random.Random(31)
    for text in _texts(rng, 150):
        events = _random_events(rng, rng.randint(1, 30))
        for fast in (True, False):
            m, got = _online(text, events, fast_path=fast)
            _assert_matches_oracle(text, events, m, got)
        # restored from JSON at a random point of the stream: same verdicts as never restored
        m, got, cut = Monitor(synthesize(text, CONSTANTS), sort_threshold=2), [], rng.randrange(len(events) + 1)
        for i, e in enumerate(events):
            if i == cut:
                m = Monitor.from_dict(json.loads(json.dumps(m.to_dict())))
            got += m.feed([e])
        got += m.flush()
        _assert_matches_oracle(text, events, m, got)


def test_random_signal_free_formulas_reset_without_false_positives():
    """Overload strategy 2 recomputes the bits from the held values: still only false negatives."""
    rng = random.Random(32)
    for text in _texts(rng, 150):
        events = _random_events(rng, rng.randint(3, 30), step=(1, 3))
        truth = instance_verdicts(parse_assertion(text, CONSTANTS), events)
        approx, got = Monitor(synthesize(text, CONSTANTS), tolerant=True), []
        if rng.random() < 0.3:
            approx.drop_and_reset()  # a reset before any event keeps the empty held state's bits
        for e in events:
            approx.push(*e)
            if rng.random() < 0.15:
                approx.drop_and_reset()
            elif rng.random() < 0.5:
                got += approx.evaluate()
        got += approx.flush()
        for v in got:
            assert truth.get(v.instance_start) is False, (text, events, v)


@pytest.mark.parametrize(
    "text",
    [
        "G({!(y > 5)} -> F[0,12](x > 8))",  # fast path, antecedent true before y's first event
        "G(LIM >= 3 -> (5 > 0) U[0,6] ({!(y > 5)} && x < 2))",
        "G({true} -> X({!(y > 5)}) || F[2,9]({!a}))",
    ],
)
def test_migration_agrees_with_the_oracle_for_signal_free_propositions(text):
    rng = random.Random(text)
    program = synthesize(text, CONSTANTS)
    events = [("x", 0, 0), ("a", True, 1)] + [(s, v, t + 2) for s, v, t in _stream(rng, 1500)]
    reference = Monitor(program)
    want = reference.feed(events) + reference.flush()
    net = Network(program, rng)
    net.start_migration()  # the first migration moves a monitor that has seen no y yet
    for i, e in enumerate(events):
        if i > 0 and rng.random() < 0.02:
            net.start_migration()
        net.deliver(e)
    got = net.finish()
    assert net.migrations >= 10
    assert got == want
    assert net.active.counters == reference.counters
    _assert_matches_oracle(text, events, net.active, got)


# ---- offline: the trace ends at its last instant ---------------------------------------------------


@pytest.mark.parametrize("fast", [True, False])
def test_a_window_closing_at_the_last_timestamp_is_decided_offline(fast):
    events = [("x", v, t) for t, v in enumerate([1, 2, 3, 4])]
    result = check_trace("G[0,0](F[0,3](x > 5))", events, fast_path=fast)
    assert result.verdict == "fail" and result.pending == 0
    assert [(v.time, v.instance_start) for v in result.violations] == [(3, 0)]
    assert check_trace("G[0,0](F[0,3](x > 3))", events, fast_path=fast).verdict == "pass"
    # one millisecond more and the window reaches past the trace: not decided
    longer = check_trace("G[0,0](F[0,4](x > 5))", events, fast_path=fast)
    assert longer.verdict == "inconclusive" and longer.pending == 1
    resp = check_trace("G(x > 0 -> F[0,3](x > 5))", events, fast_path=fast)
    assert [v.instance_start for v in resp.violations] == [0] and resp.pending == 3


def test_until_and_release_windows_closing_at_the_end_are_decided_offline():
    events = [("x", v, t) for t, v in enumerate([1, 2, 3, 4])]
    assert check_trace("G[0,0]((x < 9) U[0,3] (x > 5))", events).verdict == "fail"
    assert check_trace("G[0,0]((x < 9) U[0,4] (x > 5))", events).verdict == "inconclusive"
    assert check_trace("G[0,0]((x > 5) R[0,3] (x < 9))", events).verdict == "pass"
    assert check_trace("G[0,0](X(x > 9))", events[:1]).verdict == "inconclusive"  # no next instant


@pytest.mark.parametrize("mode", ["timestamp", "event"])
def test_random_formulas_offline_match_the_complete_trace_oracle(mode):
    rng = random.Random(41 if mode == "timestamp" else 42)
    for text in _texts(rng, 200):
        events = _random_events(rng, rng.randint(1, 30), step=(1, 3) if mode == "event" else (0, 3))
        result = check_trace(text, events, constants=CONSTANTS, instant_mode=mode, fast_path=rng.random() < 0.5)
        expected = instance_verdicts(parse_assertion(text, CONSTANTS), events, mode, complete=True)
        failed = {v.instance_start for v in result.violations}
        assert failed == {ts for ts, want in expected.items() if want is False}, (text, events)
        assert result.pending == sum(1 for want in expected.values() if want is None), (text, events)
        want = "fail" if failed else "inconclusive" if result.pending else "pass"
        assert result.verdict == want
