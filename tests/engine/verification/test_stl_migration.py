"""Lossless monitor migration (Fig. 3.43, spec 03 §11.1, acceptance check 13), in process.

A simulated verification network: every event is delivered to each handler copy subscribed to the
monitor; migrations follow the protocol steps with events arriving between every step, and each migration's
state travels as JSON. The verdicts of the migrated monitor must equal those of an unmigrated one.
"""

import json
import random
import zlib

import pytest

from continuum.engine.core.errors import InputError
from continuum.engine.verification.stl_monitor import (
    Monitor,
    migrate_begin,
    migrate_complete,
    migrate_handover,
    migrate_t0,
    standby_copy,
    synthesize,
)

ASSERTIONS = [
    "G(x >= 7 -> F[0,40](y >= 7))",  # response fast path
    "G(F[0,10](a) -> (x > 2) U[2,30] (y < 1 || X(b)))",  # antecedent- and consequent-pending instances
    "G[100,5000](a && !b -> X(X(x != 3)) xor F[5,15](y > 4))",
    "G((x > 5) R[0,20] (y > 0) -> true xor a)",
]


def _stream(rng, n):
    """Timestamps are non-decreasing; ties are common, so instants straddle subscriptions."""
    ts, out = 0, []
    for _ in range(n):
        ts += rng.choice([0, 1, 1, 2, 3, 5])
        sig = rng.choice(["a", "b", "x", "y"])
        value = rng.random() < 0.5 if sig in ("a", "b") else rng.randint(0, 10)
        out.append((sig, value, ts))
    return out


class Network:
    """The verification network of Fig. 3.42 for one monitor, with the Fig. 3.43 protocol as a state machine."""

    def __init__(self, program, rng, handlers=4, **options):
        self.program, self.rng, self.options = program, rng, options
        self.where = 0
        self.active = Monitor(program, **options)
        self.subscribed = {0: self.active}  # handler -> its copy that receives events
        self.handlers = handlers
        self.migration = None  # (phase, source, destination handler, destination copy, payload)
        self.verdicts = []
        self.migrations = 0
        self.payload_sizes = []

    def start_migration(self):
        if self.migration is None:
            target = self.rng.choice([h for h in range(self.handlers) if h != self.where])
            migrate_begin(self.active)  # steps 1-2: MIGRATE received, monitor off the scheduler
            self.migration = {"phase": "announced", "to": target, "wait": self.rng.randint(0, 3)}

    def deliver(self, event):
        for copy in self.subscribed.values():
            copy.push(*event)
        self._advance_protocol()
        if self.migration is None or self.migration["phase"] == "announced":
            # the handler's scheduler evaluates in time slices: a random number of instants per turn
            self.verdicts += self.active.evaluate(max_instants=self.rng.randint(0, 4))

    def _advance_protocol(self):
        mig = self.migration
        if mig is None:
            return
        if mig["phase"] == "announced":
            if mig["wait"] > 0:  # H2 takes a while to attach its callbacks
                mig["wait"] -= 1
                return
            mig["copy"] = standby_copy(self.program, **self.options)  # step 3
            self.subscribed[mig["to"]] = mig["copy"]
            mig["phase"] = "buffering"
        elif mig["phase"] == "buffering":
            t0 = migrate_t0(mig["copy"])  # step 4
            if t0 is not None:
                payload = migrate_handover(self.active, t0)  # step 5: H1 detaches and sends
                del self.subscribed[self.where]
                text = json.dumps(payload)
                self.payload_sizes.append(len(text))
                mig["payload"] = json.loads(text)
                mig["phase"] = "in flight"
                mig["latency"] = self.rng.randint(0, 3)
        elif mig["phase"] == "in flight":
            if mig["latency"] > 0:
                mig["latency"] -= 1
                return
            migrate_complete(mig["copy"], mig["payload"])  # step 6
            self.active, self.where = mig["copy"], mig["to"]
            self.migration = None
            self.migrations += 1

    def finish(self):
        while self.migration is not None:
            self._advance_protocol()
            if self.migration and self.migration["phase"] == "buffering":
                # no more events will come: H2 sorts what it has (possibly nothing)
                payload = migrate_handover(self.active, migrate_t0(self.migration["copy"], force=True))
                del self.subscribed[self.where]
                migrate_complete(self.migration["copy"], json.loads(json.dumps(payload)))
                self.active, self.where = self.migration["copy"], self.migration["to"]
                self.migration = None
                self.migrations += 1
        self.verdicts += self.active.flush()
        return self.verdicts


@pytest.mark.parametrize("assertion", ASSERTIONS)
@pytest.mark.parametrize(("sort_threshold", "mode"), [(1, "timestamp"), (3, "timestamp"), (2, "event")])
def test_migrated_monitor_gives_the_verdicts_of_an_unmigrated_one(assertion, sort_threshold, mode):
    rng = random.Random(zlib.crc32(f"{assertion}/{sort_threshold}/{mode}".encode()))
    program = synthesize(assertion)
    events = _stream(rng, 6000)
    options = {"sort_threshold": sort_threshold, "instant_mode": mode}
    reference = Monitor(program, **options)
    want = reference.feed(events) + reference.flush()

    net = Network(program, rng, **options)
    for i, e in enumerate(events):
        if i > 0 and rng.random() < 0.01:
            net.start_migration()
        net.deliver(e)
    got = net.finish()

    assert net.migrations >= 30
    assert len(want) > 0
    assert got == want
    assert net.active.counters == reference.counters  # no event lost or evaluated twice
    assert net.active.pending_starts() == reference.pending_starts()
    assert net.active.verdict() == reference.verdict()


def test_state_moves_with_pending_instances():
    program = synthesize("G(x >= 7 -> F[0,100](y >= 7))")
    src = Monitor(program)
    src.feed([("x", 9, 0), ("y", 0, 0), ("x", 1, 10), ("x", 8, 20), ("y", 1, 30)])
    src.evaluate(final=True)
    assert src.active_instances == 3  # started at 0, 20 and 30 (x = 8 is held at 30)
    migrate_begin(src)
    src.push("y", 2, 40)  # arrives while H2 is not subscribed yet: only H1 has it
    dst = standby_copy(program)
    dst.push("y", 8, 50)
    src.push("y", 8, 50)
    assert migrate_t0(dst) is None  # one timestamp only: H2 may have missed some events of ts 50
    for e in [("x", 0, 60), ("x", 0, 70)]:
        src.push(*e)
        dst.push(*e)
    t0 = migrate_t0(dst)
    assert t0 == 60
    payload = migrate_handover(src, t0)
    # instants 40 and 50 travel compressed: delta timestamps and bit masks (bit 0: x >= 7, bit 1: y >= 7)
    assert payload["state"]["pre"]["t0"] == 40 and payload["state"]["pre"]["dts"] == [0, 10]
    assert payload["state"]["pre"]["bits"] == [0b01, 0b11]
    assert payload["state"]["pool"] == [[0, 100, 0], [20, 120, 20], [30, 130, 30]]
    src.push("y", 9, 80)  # H1 is detached: ignored
    assert src.backlog == 0
    migrate_complete(dst, json.loads(json.dumps(payload)))
    assert dst.active_instances == 3
    assert dst.feed([("x", 0, 200)]) == []  # y >= 7 at 50 discharges the instances of 0, 20, 30 and 40
    assert dst.active_instances == 0 and dst.verdict() == "pass"
    assert dst.counters["events"] == 9 and dst.counters["instants"] == 8


def test_equal_timestamps_straddling_the_subscription_are_not_lost():
    program = synthesize("G(a -> X(b))")
    stream = [("a", True, 0), ("b", False, 0), ("a", False, 5), ("b", True, 5), ("b", True, 5), ("a", False, 6)]
    src = Monitor(program)
    src.feed(stream[:2])
    migrate_begin(src)
    src.push(*stream[2])  # same instant as the next events, before H2 subscribed
    dst = standby_copy(program)
    for e in stream[3:]:
        src.push(*e)
        dst.push(*e)
    payload = migrate_handover(src, migrate_t0(dst))
    assert payload["t0"] == 6
    migrate_complete(dst, payload)
    got = dst.flush()
    reference = Monitor(program)
    assert got == reference.feed(stream) + reference.flush()
    assert dst.counters == reference.counters


def test_complete_rejects_other_documents():
    with pytest.raises(InputError, match="payload"):
        migrate_complete(standby_copy(synthesize("G(a)")), {"format": "nope"})
