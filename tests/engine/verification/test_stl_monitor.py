"""Monitor synthesis and semantics (spec 03 §8, acceptance checks 12-13), against a reference oracle."""

import json
import random

import pytest

from continuum.engine.core.errors import InputError
from continuum.engine.verification.stl_monitor import Monitor, Violation, check_trace, synthesize
from continuum.engine.verification.stl_parser import parse_assertion

from .stl_oracle import instance_verdicts
from .test_stl_parser import _random_formula

# ---- Fig. 3.41: synthesis and the compressed buffer ------------------------------------------------


def test_placeholder_substitution():
    program = synthesize("G(speed > 0 -> F[0,5000](arrived))")
    assert program.skeleton == "G(p0 -> F[0,5000](p1))"
    assert [p.text for p in program.placeholders] == ["speed > 0", "arrived"]
    assert program.deps == {"speed": [0], "arrived": [1]}


def test_repeated_proposition_shares_one_placeholder():
    program = synthesize("G(x > 1 && y -> F[0,5](x > 1 || {y && x > 1}))")
    assert program.skeleton == "G(p0 && p1 -> F[0,5](p0 || {p2}))" or program.skeleton.startswith("G(p0 && p1")
    assert [p.text for p in program.placeholders] == ["x > 1", "y", "{y && x > 1}"]


def test_fig_3_41_sort_and_compress():
    # Events arrive out of order; with sort_threshold = 3 they are sorted once three are buffered.
    m = Monitor("G(speed > 10 -> F[0,5000](arrived))", sort_threshold=3)
    m.push("speed", 8.1, 10022)
    m.push("arrived", False, 10021)
    assert m.compressed() == []  # two events: not sorted yet
    m.push("speed", 17.3, 10023)
    compressed = m.compressed()
    assert [ts for ts, _ in compressed] == [10021, 10022, 10023]
    assert [int(bits[0]) for _, bits in compressed] == [0, 0, 1]  # the placeholder of "speed > 10"


# ---- Fig. 3.44: next, dropping with and without reset ----------------------------------------------


def _run_pairs(pairs, drop=(), reset=True):
    """Feed (a, b) instants of always(a -> next(b)); drop the listed instants (with or without reset)."""
    m = Monitor("always(a -> next(b))", record_outputs=True, tolerant=True)
    violations = []
    for i, (a, b) in enumerate(pairs):
        m.push("a", a, i)
        m.push("b", b, i)
        if i in drop:
            if reset:
                m.drop_and_reset()
            else:  # the naive alternative the thesis warns about: throw the instant away, keep the state
                m.ready.clear()
            continue
        violations += m.evaluate(final=True)
    return [o for _, o in m.outputs], violations


def test_fig_3_44_false_negative_trace():
    outputs, violations = _run_pairs([(1, 0), (0, 0), (0, 1)])
    assert outputs == [1, 0, 1]
    assert violations == [Violation(1, 0, ("b", 0, 1))]
    # Dropping e1 (with the reset the platform always does) hides the failure: a false negative.
    outputs, violations = _run_pairs([(1, 0), (0, 0), (0, 1)], drop={1})
    assert outputs == [1, 1] and violations == []


def test_fig_3_44_false_positive_trace():
    outputs, violations = _run_pairs([(1, 0), (0, 1), (0, 0)])
    assert outputs == [1, 1, 1] and violations == []
    # Dropping e1 WITHOUT reset: e2's b = 0 answers e0's pending "next b": a false positive.
    outputs, violations = _run_pairs([(1, 0), (0, 1), (0, 0)], drop={1}, reset=False)
    assert outputs == [1, 0] and len(violations) == 1
    # With the reset there is none.
    outputs, violations = _run_pairs([(1, 0), (0, 1), (0, 0)], drop={1}, reset=True)
    assert outputs == [1, 1] and violations == []


def test_lagging_trigger():
    m = Monitor("G(x < 5)", tolerant=True)
    for t in range(0, 400, 10):
        m.push("x", 1, t)
    assert not m.lagging(max_lag_ms=500, max_buffer=100)
    assert m.lagging(max_lag_ms=300, max_buffer=100)  # 390 ms between the oldest and newest waiting events
    assert m.lagging(max_lag_ms=500, max_buffer=10)  # 40 events wait
    m.drop_and_reset()
    assert not m.lagging(max_lag_ms=0, max_buffer=0) and m.counters["dropped_events"] == 40


def test_drop_needs_a_tolerant_monitor():
    m = Monitor("G(a -> X(b))")
    with pytest.raises(InputError, match="not tolerant"):
        m.drop_and_reset()


# ---- G(speed > 0 -> F[0,5000](arrived)) --------------------------------------------------------------

SPEED = "G(speed > 0 -> F[0,5000](arrived))"


@pytest.mark.parametrize("fast", [True, False])
def test_response_fails_exactly_after_5000_ms(fast):
    base = [("speed", 3.0, 1000), ("arrived", False, 1000), ("speed", 0.0, 1001)]
    on_time = check_trace(SPEED, [*base, ("arrived", True, 6000), ("arrived", False, 9000)], fast_path=fast)
    assert on_time.verdict == "pass" and on_time.violations == []
    late = check_trace(SPEED, [*base, ("arrived", True, 6001)], fast_path=fast)
    assert late.verdict == "fail"
    assert late.violations == [Violation(6001, 1000, ("arrived", True, 6001))]
    still_open = check_trace(SPEED, [*base, ("arrived", False, 5999)], fast_path=fast)
    assert still_open.verdict == "inconclusive" and still_open.pending == 1


@pytest.mark.parametrize("fast", [True, False])
def test_clock_tick_reports_the_failure_without_further_events(fast):
    m = Monitor(SPEED, fast_path=fast)
    m.feed([("speed", 1.0, 0), ("arrived", False, 0)])
    assert m.tick(5000) == [] and m.active_instances == 1
    assert m.tick(5001) == [Violation(5001, 0, None)]
    assert m.verdict() == "fail" and m.active_instances == 0
    m.push("arrived", True, 4000)  # too late: that instant is closed
    m.flush()
    assert m.counters["late_events"] == 1


def test_sample_and_hold_starts_instances_at_later_events():
    # speed stays positive while other signals change: each instant is a new instance.
    r = check_trace(SPEED, [("speed", 1, 0), ("other", 1, 100), ("arrived", True, 5050), ("speed", 0, 5060)])
    assert r.verdict == "fail"
    assert [v.instance_start for v in r.violations] == [0]


def test_g_interval_limits_instance_starts():
    events = [("x", v, t) for t, v in enumerate([0, 9, 9, 0, 9])]
    assert check_trace("G[0,2](x < 5)", events).violations == [
        Violation(1, 1, ("x", 9, 1)),
        Violation(2, 2, ("x", 9, 2)),
    ]
    assert check_trace("G[3,4](x < 5)", events).violations == [Violation(4, 4, ("x", 9, 4))]


def test_until_conventions():
    events = [("a", 1, 0), ("b", 0, 0), ("a", 1, 1), ("a", 0, 2), ("b", 1, 2), ("b", 0, 3)]
    assert check_trace("G[0,0](a U[0,5] b)", events).verdict == "pass"  # a on [0,2), b at 2
    assert check_trace("G[0,0](a U[0,5] b)", events, until_inclusive=True).verdict == "fail"


def test_release_is_dual_of_until():
    # b must hold until (and including) the instant a releases it, within 5 ms
    ok = [("b", 1, 0), ("a", 0, 0), ("b", 1, 1), ("a", 1, 1), ("b", 0, 2), ("a", 0, 2)]
    assert check_trace("G[0,0](a R[0,5] b)", ok).verdict == "pass"
    bad = [("b", 1, 0), ("a", 0, 0), ("b", 0, 1), ("a", 1, 1)]
    assert check_trace("G[0,0](a R[0,5] b)", bad).verdict == "fail"


def test_instance_counters():
    m = Monitor("G(F[0,10](a) -> F[0,20](b))", fast_path=False)
    m.feed([("a", 0, 0), ("b", 0, 0), ("a", 0, 1)])
    assert m.antecedent_pending == 1  # the instant at ts 1 stays open until a later timestamp arrives
    m.evaluate(final=True)
    assert m.antecedent_pending == 2 and m.active_instances == 0
    m.feed([("a", 1, 2), ("a", 0, 3)])
    m.evaluate(final=True)
    assert m.antecedent_pending == 1 and m.active_instances == 3  # 0, 1, 2 wait for b; 3 waits for a
    m.feed([("b", 1, 4), ("a", 0, 5)])
    m.evaluate(final=True)
    # b at 4 discharges every consequent, and instants 4 and 5 see b (held) at once: nothing is pending.
    assert m.active_instances == 0 and m.antecedent_pending == 0
    assert m.counters["passed"] == 6 and m.verdict() == "pass"


def test_event_instant_mode():
    events = [("a", 1, 0), ("b", 0, 0), ("b", 1, 1), ("a", 0, 1)]
    # one instant per event: at the event a=1 (b not yet seen), X(b) reads the next event, b=0 at the same ts
    assert check_trace("G(a -> X(b))", events, instant_mode="event").verdict == "fail"
    assert check_trace("G(a -> X(b))", events).verdict == "pass"


def test_out_of_order_events_within_sort_threshold_are_sorted():
    events = [("x", 1, 5), ("x", 9, 3), ("x", 2, 4), ("x", 3, 6), ("x", 9, 8), ("x", 0, 7)]
    m = Monitor("G(x < 5)", sort_threshold=3)
    got = m.feed(events) + m.flush()
    assert [v.time for v in got] == [3, 8]
    assert m.counters["late_events"] == 0


def test_bad_options():
    with pytest.raises(InputError, match="sort_threshold"):
        Monitor("G(a)", sort_threshold=0)
    with pytest.raises(InputError, match="instant_mode"):
        Monitor("G(a)", instant_mode="sample")


# ---- property tests against the oracle ---------------------------------------------------------------


def _random_events(rng, n, signals=("a", "b", "x", "y"), step=(0, 3)):
    events, ts = [], 0
    for _ in range(n):
        ts += rng.randint(*step)
        sig = rng.choice(signals)
        value = rng.random() < 0.5 if sig in ("a", "b") else rng.randint(-4, 8)
        events.append((sig, value, ts))
    return events


def _monitor_instances(result, monitor_pending_starts, window_starts):
    failed = {v.instance_start for v in result.violations}
    out = {}
    for ts in window_starts:
        out[ts] = False if ts in failed else None if ts in monitor_pending_starts else True
    return out


@pytest.mark.parametrize("mode", ["timestamp", "event"])
def test_random_formulas_match_the_oracle(mode):
    rng = random.Random(11 if mode == "timestamp" else 12)
    for _ in range(150):
        g = rng.choice(["", "[0,20]", "[3,30]"])
        text = f"G{g}({_random_formula(rng, 2)} -> {_random_formula(rng, 2)})"
        events = _random_events(rng, rng.randint(1, 40), step=(1, 3) if mode == "event" else (0, 3))
        m = Monitor(text, instant_mode=mode, fast_path=False)
        violations = m.feed(events) + m.flush()
        if mode == "event":  # distinct timestamps: one instance per start ts
            assert len({e[2] for e in events}) == len(events)
        expected = instance_verdicts(parse_assertion(text), events, mode)
        got = _monitor_instances(m.result(violations), set(m.pending_starts()), expected)
        for ts, want in expected.items():
            if want is not None:
                assert got[ts] == want, (text, events, ts)
        assert m.verdict() == ("fail" if False in got.values() else "inconclusive" if None in got.values() else "pass")


def test_response_fast_path_equals_generic_progression():
    rng = random.Random(5)
    for _ in range(200):
        lo = rng.randint(0, 4)
        text = f"G{rng.choice(['', '[0,25]'])}(x > {rng.randint(0, 4)} -> F[{lo},{lo + rng.randint(0, 6)}](y >= 3))"
        events = _random_events(rng, rng.randint(1, 60), signals=("x", "y"))
        fast, slow = Monitor(text), Monitor(text, fast_path=False)
        assert fast.fast and not slow.fast
        got_fast = fast.feed(events) + fast.flush()
        got_slow = slow.feed(events) + slow.flush()
        assert got_fast == got_slow, (text, events)
        assert fast.counters == slow.counters
        assert fast.pending_starts() == slow.pending_starts()


def test_drop_and_reset_gives_no_false_positives():
    """Spec 03 §11.2: with the reset, G(A -> C) monitors can only miss violations under dropping."""
    rng = random.Random(3)
    for _ in range(200):
        text = f"G({_random_formula(rng, 1)} -> {_random_formula(rng, 2)})"
        events = _random_events(rng, rng.randint(5, 50), step=(1, 3))
        original = Monitor(text)
        truth = {v.instance_start: v.time for v in original.feed(events) + original.flush()}
        approx = Monitor(text, tolerant=True)
        got = []
        for e in events:
            approx.push(*e)
            if rng.random() < 0.15:
                approx.drop_and_reset()
            elif rng.random() < 0.5:
                got += approx.evaluate()
        got += approx.flush()
        for v in got:
            assert v.instance_start in truth, (text, events, v)
            assert truth[v.instance_start] == v.time


# ---- serialisation --------------------------------------------------------------------------------


@pytest.mark.parametrize("text", [SPEED, "G(F[0,6](a) -> (x > 2) U[1,9] (y < 0 || X(b)))", "G[0,40](a -> X(X(b)))"])
def test_state_round_trips_through_json_mid_stream(text):
    rng = random.Random(9)
    events = _random_events(rng, 300, signals=("a", "b", "x", "y", "speed", "arrived"))
    reference = Monitor(text, sort_threshold=4)
    want = reference.feed(events) + reference.flush()
    m, got = Monitor(text, sort_threshold=4), []
    for i, e in enumerate(events):
        m.push(*e)
        if i % 7 == 0:
            got += m.evaluate(max_instants=2)
        if i % 23 == 0:
            m = Monitor.from_dict(json.loads(json.dumps(m.to_dict())))
    got += m.flush()
    assert got == want
    assert m.counters == reference.counters


def test_from_dict_rejects_other_documents():
    with pytest.raises(InputError, match=r"continuum\.stlmonitor/v1"):
        Monitor.from_dict({"format": "x"})


def test_clock_ticks_change_when_not_whether_instances_fail():
    rng = random.Random(21)
    for _ in range(150):
        text = f"G({_random_formula(rng, 1)} -> {_random_formula(rng, 2)})"
        events = _random_events(rng, rng.randint(1, 50), step=(0, 4))
        plain = Monitor(text)
        want = plain.feed(events) + plain.flush()
        ticked, got = Monitor(text), []
        for e in events:
            if rng.random() < 0.3 and (ticked.closed_ts is None or e[2] - 1 > ticked.closed_ts):
                got += ticked.tick(e[2] - 1)  # every event before e[2] has been pushed
            got += ticked.feed([e])
        got += ticked.flush()
        assert sorted(v.instance_start for v in got) == sorted(v.instance_start for v in want), text
        for v in got:  # a tick can only report a failure earlier, never later
            assert v.time <= next(w.time for w in want if w.instance_start == v.instance_start)
        assert ticked.pending_starts() == plain.pending_starts()
