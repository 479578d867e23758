"""Boolean STL monitors synthesised from assertions, and their lossless migration (thesis §3.5).

Pipeline of Fig. 3.41 (spec 03 §8.3):

1. **Placeholder substitution.** Every proposition of the assertion becomes a one-bit placeholder
   ``p0..pn`` (:func:`synthesize`); ``G(speed > 0 -> F[0,5000](arrived))`` becomes
   ``G(p0 -> F[0,5000](p1))``.
2. **Evaluation function.** :meth:`Monitor._eval_instant` advances the monitor by one instant over the
   placeholder bits. Each instant of the G window starts an *instance* of ``antecedent -> consequent``;
   an instance whose antecedent or consequent needs future instants stays *pending* (antecedent-pending or
   consequent-pending, i.e. *active*, kept apart). Pending obligations are residual formulas progressed
   instant by instant (formula progression with windows anchored at absolute times), so any nesting of
   ``F``, ``U``, ``R``, ``X`` and boolean operators is monitored exactly. The response pattern
   ``G(A -> F[a,b] C)`` with propositional A and C (by far the most common) keeps its instances in a
   queue ordered by deadline instead, O(1) amortised per instant; both paths give identical verdicts
   (a property test checks it).
3. **Handler side.** Events ``(variable, value, timestamp)`` are appended to an event buffer; when it
   holds ``sort_threshold`` events it is sorted by timestamp into the sorted buffer, from which the
   evaluation consumes instants.

Semantics (spec 03 §8.2), times in milliseconds:
  * An instant is a timestamp: events sharing a timestamp are applied together (``instant_mode="timestamp"``,
    our reading; with the thesis's distinct PTP timestamps it is exactly one instant per event, and it is
    what a CSV trace row means). ``instant_mode="event"`` makes every event its own instant.
  * Sample and hold: the placeholder bits at an instant use the latest value of every signal; a signal
    never seen makes its comparisons false (Fig. 3.41 compresses ``speed > 10`` to 0 before any speed),
    so ``{!(b > 5)}`` is true until b's first event, and a proposition reading no signal (``{true}``,
    ``1 < 2``, or one the constants fixed) keeps its value from the first instant on. Every path (online,
    compression for migration, restore, reset) computes the bits from the held values by this one rule.
  * ``F[a,b] φ`` at t: φ at some instant with ts in [ts(t)+a, ts(t)+b]; it fails when an instant with
    ts > ts(t)+b arrives (or, with :meth:`Monitor.tick`, when the clock passes it).
  * ``φ U[a,b] ψ``: ψ at some t' in the window and φ at every instant in [t, t') (``until_inclusive=False``,
    rtamt's discrete convention; True also demands φ at t'). ``φ R[a,b] ψ = !(!φ U[a,b] !ψ)``.
  * ``X φ``: φ at the next instant. ``G[a,b]``: instances start at instants with ts - ts(first) in [a,b].
  * Verdicts: ``fail`` if some instance failed, else ``inconclusive`` if instances are still pending at the
    end of the trace, else ``pass`` (the ``stl_check`` contract). Offline (:func:`check_trace`) the trace
    ends at its last instant, so a window closing at or before it is decided (:meth:`Monitor.end_trace`).

Migration (Fig. 3.43, spec 03 §11.1) is implemented by :func:`migrate_begin`, :func:`migrate_t0`,
:func:`migrate_handover` and :func:`migrate_complete`; the monitor's complete state is JSON
(:meth:`Monitor.to_dict`/:meth:`Monitor.from_dict`), so the steps can run in different processes.
Overload strategy 2 (trace approximation, §11.2) is :meth:`Monitor.drop_and_reset`.
"""

from __future__ import annotations

import itertools
from collections import deque
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from continuum.engine.core.errors import InputError
from continuum.engine.core.unique import first_duplicate
from continuum.engine.verification import stl_parser as P

__all__ = [
    "FORMAT",
    "PAYLOAD_FORMAT",
    "Bits",
    "Event",
    "Monitor",
    "Placeholder",
    "Program",
    "Result",
    "Violation",
    "check_trace",
    "migrate_begin",
    "migrate_complete",
    "migrate_handover",
    "migrate_t0",
    "parse_trace_csv",
    "standby_copy",
    "synthesize",
]

FORMAT = "continuum.stlmonitor/v1"
PAYLOAD_FORMAT = "continuum.stlmigration/v1"

Event = tuple[str, Any, float]  # (variable, value, timestamp in ms)
Bits = list[bool]


# ===================================================================================================
# 1. Synthesis: placeholders and the node table of the evaluation function
# ===================================================================================================


@dataclass(frozen=True)
class Placeholder:
    name: str  # "p0", "p1", ...
    prop: P.Prop
    variables: frozenset[str]

    @property
    def text(self) -> str:
        return self.prop.text()


@dataclass
class Program:
    """A synthesised monitor: placeholders plus the formula over them as a table of nodes.

    Node kinds: ``("S", fn)`` a state (propositional) formula with ``fn(bits) -> bool``; ``("not", c)``,
    ``("and", c1, c2)``, ``("or", ...)``, ``("xor", ...)``; ``("F", a, b, c)``; ``("U", a, b, l, r)``;
    ``("X", c)``. ``R`` is rewritten to ``not U``.
    """

    assertion: P.Assertion
    constants: dict[str, float]
    placeholders: list[Placeholder]
    nodes: list[tuple]
    antecedent: int
    consequent: int
    skeleton: str
    deps: dict[str, list[int]]  # variable -> placeholder indices that read it
    evaluators: list[Callable[[Mapping[str, Any]], bool]]

    @property
    def text(self) -> str:
        return self.assertion.source or self.assertion.text()

    @property
    def variables(self) -> set[str]:
        return set(self.deps)

    def has_intervals(self) -> bool:
        return self.assertion.interval is not None or any(n[0] in ("F", "U") for n in self.nodes)

    def is_state(self, nid: int) -> bool:
        return self.nodes[nid][0] == "S"

    def response_fast_path(self) -> bool:
        """``G(A -> F[a,b] C)`` with propositional A and C: instances kept in a deadline-ordered queue."""
        cons = self.nodes[self.consequent]
        return self.is_state(self.antecedent) and cons[0] == "F" and self.is_state(cons[3])


def synthesize(assertion: str | P.Assertion, constants: Mapping[str, float] | None = None) -> Program:
    """Parse (if needed) and synthesise the monitor program: placeholders + evaluation function."""
    constants = dict(constants or {})
    a = assertion if isinstance(assertion, P.Assertion) else P.parse_assertion(assertion, constants)
    builder = _Builder()
    ant = builder.node(a.antecedent)
    cons = builder.node(a.consequent)
    skeleton = P.Assertion(a.interval, builder.skeleton(a.antecedent), builder.skeleton(a.consequent)).text()
    deps: dict[str, list[int]] = {}
    for ph in builder.placeholders:
        for v in sorted(ph.variables):
            deps.setdefault(v, []).append(int(ph.name[1:]))
    evaluators = [P.compile_prop(ph.prop) for ph in builder.placeholders]
    return Program(a, constants, builder.placeholders, builder.nodes, ant, cons, skeleton, deps, evaluators)


class _Builder:
    def __init__(self) -> None:
        self.placeholders: list[Placeholder] = []
        self.index: dict[P.Expr, int] = {}
        self.nodes: list[tuple] = []
        self.memo: dict[tuple, int] = {}

    def placeholder(self, prop: P.Prop) -> int:
        if prop.expr not in self.index:
            self.index[prop.expr] = len(self.placeholders)
            name = f"p{len(self.placeholders)}"
            self.placeholders.append(Placeholder(name, prop, frozenset(P.variables(prop.expr))))
        return self.index[prop.expr]

    def skeleton(self, f: P.Formula) -> P.Formula:
        """The formula with every proposition replaced by its placeholder name."""
        if isinstance(f, P.Prop):
            return P.Prop(P.Var(f"p{self.placeholder(f)}"))
        if isinstance(f, P.Not):
            return P.Not(self.skeleton(f.operand))
        if isinstance(f, P.BoolOp):
            return P.BoolOp(f.op, self.skeleton(f.left), self.skeleton(f.right))
        if isinstance(f, P.Eventually):
            return P.Eventually(f.lo, f.hi, self.skeleton(f.operand))
        if isinstance(f, P.Next):
            return P.Next(self.skeleton(f.operand))
        if isinstance(f, P.Until):
            return P.Until(f.op, f.lo, f.hi, self.skeleton(f.left), self.skeleton(f.right))
        return f

    def add(self, key: tuple, make: Callable[[], tuple]) -> int:
        if key not in self.memo:
            self.memo[key] = len(self.nodes)
            self.nodes.append(make())
        return self.memo[key]

    def node(self, f: P.Formula) -> int:
        if _is_state(f):
            fn = self.state_fn(f)
            return self.add(("S", f), lambda: ("S", fn))
        if isinstance(f, P.Not):
            c = self.node(f.operand)
            return self.add(("not", c), lambda: ("not", c))
        if isinstance(f, P.BoolOp):
            kind = {"&&": "and", "||": "or", "xor": "xor"}[f.op]
            lhs, rhs = self.node(f.left), self.node(f.right)
            return self.add((kind, lhs, rhs), lambda: (kind, lhs, rhs))
        if isinstance(f, P.Eventually):
            c = self.node(f.operand)
            return self.add(("F", f.lo, f.hi, c), lambda: ("F", f.lo, f.hi, c))
        if isinstance(f, P.Next):
            c = self.node(f.operand)
            return self.add(("X", c), lambda: ("X", c))
        if isinstance(f, P.Until) and f.op == "U":
            lhs, rhs = self.node(f.left), self.node(f.right)
            return self.add(("U", f.lo, f.hi, lhs, rhs), lambda: ("U", f.lo, f.hi, lhs, rhs))
        if isinstance(f, P.Until):  # R[a,b]: !(!l U[a,b] !r)
            return self.node(P.Not(P.Until("U", f.lo, f.hi, P.Not(f.left), P.Not(f.right))))
        raise TypeError(f"not a formula node: {f!r}")

    def state_fn(self, f: P.Formula) -> Callable[[Bits], bool]:
        if isinstance(f, P.Prop):
            i = self.placeholder(f)
            return lambda bits: bits[i]
        if isinstance(f, P.Const):
            v = f.value
            return lambda bits: v
        if isinstance(f, P.Not):
            g = self.state_fn(f.operand)
            return lambda bits: not g(bits)
        assert isinstance(f, P.BoolOp)
        gl, gr = self.state_fn(f.left), self.state_fn(f.right)
        if f.op == "&&":
            return lambda bits: gl(bits) and gr(bits)
        if f.op == "||":
            return lambda bits: gl(bits) or gr(bits)
        return lambda bits: gl(bits) != gr(bits)


def _is_state(f: P.Formula) -> bool:
    if isinstance(f, (P.Prop, P.Const)):
        return True
    if isinstance(f, P.Not):
        return _is_state(f.operand)
    if isinstance(f, P.BoolOp):
        return _is_state(f.left) and _is_state(f.right)
    return False


# ===================================================================================================
# 2. Residual obligations: progression of the formula over instants
# ===================================================================================================
# A residual is True/False or a tuple:
#   ("n", nid)              node nid, to be started at the next instant it is stepped on (left by X)
#   ("F", lo, hi, nid)      eventually-nid within the absolute window [lo, hi]
#   ("U", lo, hi, l, r)     l until r within the absolute window [lo, hi]
#   ("!", r) ("&", r...) ("|", r...) ("^", r1, r2)


def _and(items: Iterable) -> Any:
    out: list = []
    for r in items:
        if r is False:
            return False
        if r is True:
            continue
        for x in r[1:] if r[0] == "&" else (r,):
            if x not in out:
                out.append(x)
    if not out:
        return True
    return out[0] if len(out) == 1 else ("&", *out)


def _or(items: Iterable) -> Any:
    out: list = []
    for r in items:
        if r is True:
            return True
        if r is False:
            continue
        for x in r[1:] if r[0] == "|" else (r,):
            if x not in out:
                out.append(x)
    if not out:
        return False
    return out[0] if len(out) == 1 else ("|", *out)


def _not(r: Any) -> Any:
    if r is True or r is False:
        return not r
    return r[1] if r[0] == "!" else ("!", r)


def _xor(a: Any, b: Any) -> Any:
    if (a is True or a is False) and (b is True or b is False):
        return a != b
    if a is True or a is False:
        return _not(b) if a else b
    if b is True or b is False:
        return _not(a) if b else a
    return False if a == b else ("^", a, b)


class _Stepper:
    """Progresses residuals by one instant ``(ts, bits)``."""

    def __init__(self, program: Program, until_inclusive: bool):
        self.nodes = program.nodes
        self.inclusive = until_inclusive
        self.ts = 0.0
        self.bits: Bits = []

    def start(self, nid: int) -> Any:
        node = self.nodes[nid]
        kind = node[0]
        if kind == "S":
            return node[1](self.bits)
        if kind == "F":
            return self.step(("F", self.ts + node[1], self.ts + node[2], node[3]))
        if kind == "U":
            return self.step(("U", self.ts + node[1], self.ts + node[2], node[3], node[4]))
        if kind == "X":
            return ("n", node[1])
        if kind == "not":
            return _not(self.start(node[1]))
        if kind == "and":
            left = self.start(node[1])
            return False if left is False else _and((left, self.start(node[2])))
        if kind == "or":
            left = self.start(node[1])
            return True if left is True else _or((left, self.start(node[2])))
        return _xor(self.start(node[1]), self.start(node[2]))

    def step(self, r: Any) -> Any:
        if r is True or r is False:
            return r
        tag = r[0]
        ts = self.ts
        if tag == "n":
            return self.start(r[1])
        if tag == "F":
            if ts > r[2]:
                return False
            if ts < r[1]:
                return r
            now = self.start(r[3])
            return True if now is True else r if now is False else _or((now, r))
        if tag == "U":
            if ts > r[2]:
                return False
            psi = self.start(r[4]) if ts >= r[1] else False
            if psi is True and not self.inclusive:
                return True
            phi = self.start(r[3])
            if self.inclusive:
                return _and((phi, _or((psi, r))))
            return _or((psi, _and((phi, r))))
        if tag == "!":
            return _not(self.step(r[1]))
        if tag == "&":
            return _and(self.step(x) for x in r[1:])
        if tag == "|":
            return _or(self.step(x) for x in r[1:])
        return _xor(self.step(r[1]), self.step(r[2]))

    def expire(self, r: Any, now: float, inclusive: bool = False) -> Any:
        """Decide the windows that closed before ``now`` (no instant with ts <= now can still come), or with
        ``inclusive`` also those closing at ``now`` (the trace ended with the instant ``now``)."""
        if r is True or r is False:
            return r
        tag = r[0]
        if tag in ("F", "U"):
            return False if r[2] < now or (inclusive and r[2] <= now) else r
        if tag == "n":
            return r
        if tag == "!":
            return _not(self.expire(r[1], now, inclusive))
        if tag == "&":
            return _and(self.expire(x, now, inclusive) for x in r[1:])
        if tag == "|":
            return _or(self.expire(x, now, inclusive) for x in r[1:])
        return _xor(self.expire(r[1], now, inclusive), self.expire(r[2], now, inclusive))


def _to_json(r: Any) -> Any:
    return r if r is True or r is False else [_to_json(x) if isinstance(x, tuple) else x for x in r]


def _from_json(r: Any) -> Any:
    if r is True or r is False:
        return r
    return tuple(_from_json(x) if isinstance(x, list) else x for x in r)


# ===================================================================================================
# 3. The monitor
# ===================================================================================================


@dataclass(frozen=True)
class Violation:
    """An instance that failed: the instant that decided it (``time``, ``event``) and where it started."""

    time: float
    instance_start: float
    # the last event of the deciding instant; None when a clock tick or the end of the trace decided it
    event: Event | None

    def to_dict(self) -> dict:
        event = None if self.event is None else list(self.event)
        return {"time": self.time, "instance_start": self.instance_start, "event": event}


@dataclass
class Result:
    verdict: str  # "pass" | "fail" | "inconclusive"
    violations: list[Violation]
    events: int
    instants: int
    pending: int
    outputs: list[tuple[float, int]] = field(default_factory=list)

    def to_dict(self) -> dict:
        return {
            "verdict": self.verdict,
            "violations": [v.to_dict() for v in self.violations],
            "events": self.events,
            "instants": self.instants,
            "pending": self.pending,
        }


_COUNTERS = ("events", "instants", "passed", "failed", "late_events", "dropped_events", "resets")


class Monitor:
    """An online monitor of one assertion (the "monitor" of Fig. 3.39; its handler feeds it events).

    ``push`` only buffers (the ROS callback of Fig. 3.41); ``evaluate`` consumes complete instants from
    the sorted buffer and returns the violations it found; ``feed`` does both. ``finish`` flushes the
    buffers at the end of a trace and returns the :class:`Result`.
    """

    def __init__(
        self,
        program: Program | str,
        *,
        sort_threshold: int = 1,
        instant_mode: str = "timestamp",
        until_inclusive: bool = False,
        tolerant: bool = False,
        fast_path: bool = True,
        record_outputs: bool = False,
        constants: Mapping[str, float] | None = None,
    ):
        if isinstance(program, str):
            program = synthesize(program, constants)
        if sort_threshold < 1:
            raise InputError("sort_threshold must be >= 1", field="sort_threshold")
        if instant_mode not in ("timestamp", "event"):
            raise InputError(f"instant_mode must be 'timestamp' or 'event', not {instant_mode!r}", "instant_mode")
        self.program = program
        self.sort_threshold = sort_threshold
        self.instant_mode = instant_mode
        self._by_ts = instant_mode == "timestamp"
        self.until_inclusive = until_inclusive
        self.tolerant = tolerant  # may drop events and reset under overload (strategy 2)
        self.fast = fast_path and program.response_fast_path()
        self.record_outputs = record_outputs
        self.outputs: list[tuple[float, int]] = []
        self._stepper = _Stepper(program, until_inclusive)
        cons = program.nodes[program.consequent]
        if self.fast:
            self._ant_fn = program.nodes[program.antecedent][1]
            self._cons_lo, self._cons_hi = cons[1], cons[2]
            self._cons_fn = program.nodes[cons[3]][1]
        g = program.assertion.interval
        self._g_lo, self._g_hi = (0.0, float("inf")) if g is None else g
        self.suspended = False  # removed from the handler's scheduler (migration step 2a, or standby copy)
        self.detached = False  # migrated away: no longer receives events
        self._reset_state()
        self.held: dict[str, Any] = {}
        # the placeholder bits of the empty held state: a proposition reading no signal (``5 > 0``, one that
        # constants fixed) or true while its signal is unseen (``{!(b > 5)}``) is true from the first instant,
        # exactly as compression, restore and reset compute them (sample and hold, never-seen = missing)
        self.bits: Bits = _bits_of(program, self.held)
        self.raw: list[Event] = []  # event buffer (unsorted)
        self.ready: deque[Event] = deque()  # sorted buffer, not yet evaluated
        self.pre: deque[tuple[float, int, Event | None]] = deque()  # compressed instants received by migration
        self.ts_start: float | None = None
        self.closed_ts: float | None = None  # timestamp of the last evaluated (closed) instant
        self.counters = dict.fromkeys(_COUNTERS, 0)

    def _reset_state(self) -> None:
        self.pending: list[list] = []  # generic instances: [start_ts, antecedent residual, consequent residual]
        self.pool: deque[tuple[float, float, float]] = deque()  # fast path: (lo, hi, start_ts) in deadline order

    # ---- buffering (the topic callbacks) -------------------------------------------------------
    def push(self, variable: str, value: Any, ts: float) -> None:
        """Append one event to the event buffer; sort it into the sorted buffer at ``sort_threshold``."""
        if self.detached:
            return
        ready = self.ready
        if self.sort_threshold == 1 and (not ready or ready[-1][2] <= ts):
            ready.append((variable, value, ts))  # already in order: nothing to sort
            return
        self.raw.append((variable, value, ts))
        if len(self.raw) >= self.sort_threshold:
            self._sort()

    def _sort(self) -> None:
        raw = sorted(self.raw, key=_ts)
        self.raw = []
        ready = self.ready
        if ready and ready[-1][2] > raw[0][2]:
            raw = sorted([*ready, *raw], key=_ts)  # stable: earlier arrivals first among equal timestamps
            ready.clear()
        ready.extend(raw)

    def feed(self, events: Iterable[Event]) -> list[Violation]:
        """Push events and evaluate every instant that is complete (online use)."""
        for var, value, ts in events:
            self.push(var, value, ts)
        return self.evaluate()

    # ---- evaluation ----------------------------------------------------------------------------
    def evaluate(self, max_instants: int | None = None, final: bool = False) -> list[Violation]:
        """Evaluate complete instants from the buffers; ``final`` also closes the last open instant."""
        out: list[Violation] = []
        if self.suspended or self.detached:
            return out
        budget = max_instants if max_instants is not None else -1
        pre, ready = self.pre, self.ready
        while budget != 0:
            if pre:
                ts, mask, event = pre.popleft()
                self.bits = _unmask(mask, len(self.bits))
                self._eval_instant(ts, event, out)
            elif ready:
                if not self._next_instant(final, out):
                    break
            else:
                break
            budget -= 1
        return out

    def _next_instant(self, final: bool, out: list[Violation]) -> bool:
        """Apply the events of the oldest instant in the sorted buffer and evaluate it, if it is complete."""
        ready = self.ready
        ts = ready[0][2]
        by_ts = self._by_ts
        if by_ts and not final and ready[-1][2] == ts:
            return False  # more events with this timestamp may still come
        closed = self.closed_ts
        if closed is not None and (ts < closed or (ts == closed and by_ts)):
            self._apply(ready.popleft())  # late event: its value holds from now on, no instant of its own
            self.counters["late_events"] += 1
            return True
        held, bits, deps, evaluators = self.held, self.bits, self.program.deps, self.program.evaluators
        n = 0
        while True:  # the hot loop: inlined _apply
            event = ready.popleft()
            var = event[0]
            held[var] = event[1]
            idx = deps.get(var)
            if idx:
                for i in idx:
                    bits[i] = evaluators[i](held)
            n += 1
            if not by_ts or not ready or ready[0][2] != ts:
                break
        self.counters["events"] += n
        self._eval_instant(ts, event, out)
        return True

    def _apply(self, event: Event) -> None:
        var, value, _ = event
        self.held[var] = value
        self.counters["events"] += 1
        idx = self.program.deps.get(var)
        if idx:
            held, bits, evaluators = self.held, self.bits, self.program.evaluators
            for i in idx:
                bits[i] = evaluators[i](held)

    def _eval_instant(self, ts: float, event: Event | None, out: list[Violation]) -> None:
        """The evaluation function: one step of every pending instance, then a new instance at ``ts``."""
        counters = self.counters
        counters["instants"] += 1
        self.closed_ts = ts
        start = self.ts_start
        if start is None:
            start = self.ts_start = ts
        mark = len(out)
        if self.pending:
            self._step_pending(ts, event, out)
        in_window = self._g_lo <= ts - start <= self._g_hi
        if self.fast:  # G(A -> F[a,b] C), inlined: this is the hot path of most monitors
            pool, bits = self.pool, self.bits
            if pool:
                while pool and pool[0][1] < ts:
                    out.append(Violation(ts, pool.popleft()[2], event))
                if pool and self._cons_fn(bits):
                    n = 0
                    while pool and pool[0][0] <= ts:
                        pool.popleft()
                        n += 1
                    counters["passed"] += n
            if in_window:
                if not self._ant_fn(bits) or (self._cons_lo == 0 and self._cons_fn(bits)):
                    counters["passed"] += 1  # vacuous, or the consequent holds right away
                else:
                    pool.append((ts + self._cons_lo, ts + self._cons_hi, ts))
        elif in_window:
            self._new_instance(ts, event, out)
        found = len(out) - mark
        if found:
            if found > 1:
                out[mark:] = sorted(out[mark:], key=_start)
            counters["failed"] += found
        if self.record_outputs:
            self.outputs.append((ts, 0 if found else 1))

    def _step_pending(self, ts: float, event: Event | None, found: list[Violation]) -> None:
        st = self._stepper
        st.ts, st.bits = ts, self.bits
        keep = []
        for inst in self.pending:
            ant = inst[1]
            if ant is not True:
                ant = st.step(ant)
            cons = st.step(inst[2])
            if not self._settle(inst[0], ant, cons, ts, event, found):
                inst[1], inst[2] = ant, cons
                keep.append(inst)
        self.pending = keep

    def _settle(self, start: float, ant: Any, cons: Any, ts: float, event, found: list[Violation]) -> bool:
        """Record the instance's verdict if it is decided; return whether it is."""
        if ant is False or cons is True:
            self.counters["passed"] += 1
            return True
        if ant is True and cons is False:
            found.append(Violation(ts, start, event))
            return True
        return False

    def _new_instance(self, ts: float, event: Event | None, found: list[Violation]) -> None:
        st = self._stepper
        st.ts, st.bits = ts, self.bits
        ant = st.start(self.program.antecedent)
        if ant is False:
            self.counters["passed"] += 1
            return
        cons = st.start(self.program.consequent)
        if not self._settle(ts, ant, cons, ts, event, found):
            self.pending.append([ts, ant, cons])

    # ---- end of trace, clock ticks -------------------------------------------------------------
    def flush(self) -> list[Violation]:
        """Sort and evaluate everything buffered, closing the last instant."""
        if self.raw:
            self._sort()
        return self.evaluate(final=True)

    def tick(self, now: float) -> list[Violation]:
        """The clock reached ``now`` and every event with ts <= now has been pushed (spec 03 §8.2 proposal).

        Evaluates the instants up to ``now`` and fails the windows that closed before it, so a violation is
        reported even when no further event arrives.
        """
        if self.suspended or self.detached:
            return []
        if self.raw:
            self._sort()
        out: list[Violation] = []
        while self.pre:
            out.extend(self.evaluate(max_instants=len(self.pre)))
        while self.ready and self.ready[0][2] <= now:
            self._next_instant(True, out)  # every event with ts <= now is here: the instant is complete
        found: list[Violation] = []
        while self.pool and self.pool[0][1] < now:
            found.append(Violation(now, self.pool.popleft()[2], None))
        if self.pending:
            st, keep = self._stepper, []
            for inst in self.pending:
                ant = inst[1] if inst[1] is True else st.expire(inst[1], now)
                cons = st.expire(inst[2], now)
                if not self._settle(inst[0], ant, cons, now, None, found):
                    inst[1], inst[2] = ant, cons
                    keep.append(inst)
            self.pending = keep
        found.sort(key=_start)
        self.counters["failed"] += len(found)
        out.extend(found)
        if self.closed_ts is None or now > self.closed_ts:
            self.closed_ts = now
        return out

    def end_trace(self) -> list[Violation]:
        """The trace is complete: no instant follows the last evaluated one (offline checking).

        A window that closes at or before that instant has seen every instant it covers, so it is decided
        (an ``F`` or ``U`` still pending there failed); windows reaching past it, and ``X`` at the last
        instant, stay pending (inconclusive). Returns the violations this decides, timed at the last instant.
        """
        end = self.closed_ts
        if end is None or self.suspended or self.detached:
            return []
        found: list[Violation] = []
        while self.pool and self.pool[0][1] <= end:
            found.append(Violation(end, self.pool.popleft()[2], None))
        if self.pending:
            st, keep = self._stepper, []
            for inst in self.pending:
                ant = inst[1] if inst[1] is True else st.expire(inst[1], end, inclusive=True)
                cons = st.expire(inst[2], end, inclusive=True)
                if not self._settle(inst[0], ant, cons, end, None, found):
                    inst[1], inst[2] = ant, cons
                    keep.append(inst)
            self.pending = keep
        found.sort(key=_start)
        self.counters["failed"] += len(found)
        return found

    def finish(self) -> Result:
        """Flush and return the verdict of the whole trace (pending instances make it inconclusive)."""
        self.flush()
        return self.result([])

    def result(self, violations: list[Violation]) -> Result:
        return Result(
            verdict=self.verdict(),
            violations=violations,
            events=self.counters["events"],
            instants=self.counters["instants"],
            pending=self.pending_count,
            outputs=list(self.outputs),
        )

    def verdict(self) -> str:
        if self.counters["failed"]:
            return "fail"
        return "inconclusive" if self.pending_count else "pass"

    # ---- instance accounting (priority of overload strategy 1) ---------------------------------
    @property
    def pending_count(self) -> int:
        return len(self.pending) + len(self.pool)

    @property
    def active_instances(self) -> int:
        """Instances whose antecedent fired and whose consequent is still pending."""
        return len(self.pool) + sum(1 for inst in self.pending if inst[1] is True)

    @property
    def antecedent_pending(self) -> int:
        return sum(1 for inst in self.pending if inst[1] is not True)

    def pending_starts(self) -> list[float]:
        return sorted([inst[0] for inst in self.pending] + [p[2] for p in self.pool])

    @property
    def backlog(self) -> int:
        """Events (and received compressed instants) waiting to be evaluated."""
        return len(self.raw) + len(self.ready) + len(self.pre)

    def oldest_unevaluated(self) -> float | None:
        stamps = [e[2] for e in self.raw] + ([self.ready[0][2]] if self.ready else [])
        stamps += [self.pre[0][0]] if self.pre else []
        return min(stamps) if stamps else None

    # ---- overload strategy 2: trace approximation ----------------------------------------------
    def lagging(self, max_lag_ms: float = 500.0, max_buffer: int = 10_000) -> bool:
        """The drop trigger of spec 03 §11.2 (proposal), in event time: more than ``max_buffer`` events wait,
        or the newest buffered event is more than ``max_lag_ms`` after the oldest one not evaluated."""
        if self.backlog > max_buffer:
            return True
        oldest = self.oldest_unevaluated()
        if oldest is None:
            return False
        newest = max([e[2] for e in self.raw] + ([self.ready[-1][2]] if self.ready else []) + [oldest])
        return newest - oldest > max_lag_ms

    def drop_and_reset(self) -> int:
        """Throw away every not-yet-evaluated event and reset the instances (spec 03 §11.2).

        The dropped events still update the held signal values (so later instants see true values) and the
        run start is kept (so ``G[a,b]`` keeps its window): after a reset every instance lives on a
        contiguous stretch of the real instants, hence a ``G(A -> C)`` monitor can only miss violations
        (false negatives), never report one that did not happen (false positives). Returns the number of
        events dropped. Raises InputError for a monitor not marked tolerant.
        """
        if not self.tolerant:
            raise InputError("monitor is not tolerant: hard/safety monitors never drop events", "tolerant")
        dropped = len(self.raw) + len(self.ready) + len(self.pre)
        if self.raw:
            self._sort()
        last = None
        for var, value, ts in self.ready:
            self.held[var] = value
            last = ts
        self.raw, self.pre = [], deque()
        self.ready.clear()
        self.bits = _bits_of(self.program, self.held)
        if last is not None and (self.closed_ts is None or last > self.closed_ts):
            self.closed_ts = last
        self._reset_state()
        self.counters["dropped_events"] += dropped
        self.counters["resets"] += 1
        return dropped

    # ---- compressed view (Fig. 3.41) -------------------------------------------------------------
    def compressed(self) -> list[tuple[float, tuple[bool, ...]]]:
        """The sorted, not yet evaluated instants as placeholder bit vectors (one entry per instant)."""
        n = len(self.bits)
        out = [(ts, tuple(_unmask(mask, n))) for ts, mask, _ in self.pre]
        instants, _ = _compress(self.program, self.held, list(self.ready), self.instant_mode)
        return out + [(ts, tuple(_unmask(mask, n))) for ts, mask, _ in instants]

    # ---- serialisation ---------------------------------------------------------------------------
    def options(self) -> dict:
        return {
            "sort_threshold": self.sort_threshold,
            "instant_mode": self.instant_mode,
            "until_inclusive": self.until_inclusive,
            "tolerant": self.tolerant,
            "fast_path": self.fast,
        }

    def to_dict(self) -> dict:
        """Everything a handler needs to continue this monitor elsewhere (JSON-able)."""
        pending = [[inst[0], _to_json(inst[1]), _to_json(inst[2])] for inst in self.pending]
        pool = [list(p) for p in self.pool] if self.fast else []
        return {
            "format": FORMAT,
            "assertion": self.program.text,
            "constants": self.program.constants,
            "options": self.options(),
            "held": dict(self.held),
            "ts_start": self.ts_start,
            "closed_ts": self.closed_ts,
            "pending": pending,
            "pool": pool,
            "pre": _pack_instants(list(self.pre)),
            "ready": [list(e) for e in self.ready],
            "raw": [list(e) for e in self.raw],
            "counters": dict(self.counters),
            "suspended": self.suspended,
            "detached": self.detached,
        }

    @classmethod
    def from_dict(cls, data: Mapping, program: Program | None = None) -> Monitor:
        """Rebuild a monitor; ``program`` may be given when the handler already has the code (Fig. 3.43)."""
        if data.get("format") != FORMAT:
            raise InputError(f"not a {FORMAT} document", field="format")
        if program is None:
            program = synthesize(data["assertion"], data.get("constants"))
        opts = dict(data.get("options", {}))
        m = cls(program, **opts)
        m._restore(data)
        return m

    def _restore(self, data: Mapping) -> None:
        self.held = dict(data["held"])
        self.bits = _bits_of(self.program, self.held)
        self.ts_start = data["ts_start"]
        self.closed_ts = data["closed_ts"]
        self.pending = [[s, _from_json(a), _from_json(c)] for s, a, c in data["pending"]]
        if self.fast:
            self.pool = deque(tuple(p) for p in data["pool"])
        elif data["pool"]:  # a pool written by a fast-path monitor becomes generic instances
            child = self.program.nodes[self.program.consequent][3]
            for lo, hi, start in data["pool"]:
                self.pending.append([start, True, ("F", lo, hi, child)])
            self.pending.sort(key=lambda inst: inst[0])
        self.pre = deque(_unpack_instants(data["pre"]))
        self.ready = deque(tuple(e) for e in data["ready"])
        self.raw = [tuple(e) for e in data["raw"]]
        self.counters = {k: int(data["counters"].get(k, 0)) for k in _COUNTERS}
        self.suspended = bool(data.get("suspended", False))
        self.detached = bool(data.get("detached", False))


def _bits_of(program: Program, held: Mapping[str, Any]) -> Bits:
    return [fn(held) for fn in program.evaluators]


def _ts(e: Event) -> float:
    return e[2]


def _start(v: Violation) -> float:
    return v.instance_start


def _unmask(mask: int, n: int) -> Bits:
    return [bool(mask >> i & 1) for i in range(n)]


def _mask(bits: Sequence[bool]) -> int:
    return sum(1 << i for i, b in enumerate(bits) if b)


def _compress(
    program: Program, held: Mapping[str, Any], events: list[Event], mode: str
) -> tuple[list[tuple[float, int, Event]], dict[str, Any]]:
    """Fig. 3.41's compression: sorted events -> one placeholder bit mask per instant (with its timestamp
    and last event), starting from the held values ``held``; also returns the held values at the end."""
    held = dict(held)
    bits = _bits_of(program, held)
    out = []
    for group in _instants(events, mode):
        for var, value, _ in group:
            held[var] = value
            for i in program.deps.get(var, ()):
                bits[i] = program.evaluators[i](held)
        out.append((group[-1][2], _mask(bits), group[-1]))
    return out, held


def _instants(events: list[Event], mode: str) -> list[list[Event]]:
    groups: list[list[Event]] = []
    for e in events:
        if mode == "timestamp" and groups and groups[-1][-1][2] == e[2]:
            groups[-1].append(e)
        else:
            groups.append([e])
    return groups


def _pack_instants(items: list[tuple[float, int, Event | None]]) -> dict:
    """Compressed instants: delta timestamps, one bit mask per instant, and the deciding event."""
    if not items:
        return {"t0": None, "dts": [], "bits": [], "events": []}
    t0 = items[0][0]
    stamps = [ts for ts, _, _ in items]
    dts = [0] + [b - a for a, b in itertools.pairwise(stamps)]
    if list(itertools.accumulate(dts, initial=t0))[1:] != stamps:
        return {"t0": t0, "ts": stamps, "bits": [m for _, m, _ in items], "events": [_ev(e) for _, _, e in items]}
    return {
        "t0": t0,
        "dts": dts,
        "bits": [m for _, m, _ in items],
        "events": [_ev(e) for _, _, e in items],
    }


def _ev(e: Event | None) -> list | None:
    return None if e is None else list(e)


def _unpack_instants(packed: Mapping) -> list[tuple[float, int, Event | None]]:
    if "ts" in packed:  # timestamps that deltas would not reproduce exactly (floats)
        stamps = list(packed["ts"])
    else:
        stamps = list(itertools.accumulate(packed["dts"], initial=packed["t0"]))[1:] if packed["dts"] else []
    return [
        (ts, mask, None if event is None else tuple(event))
        for ts, mask, event in zip(stamps, packed["bits"], packed["events"], strict=True)
    ]


# ===================================================================================================
# 4. Offline use
# ===================================================================================================


def check_trace(
    assertion: str | Program,
    events: Iterable[Event],
    constants: Mapping[str, float] | None = None,
    **options: Any,
) -> Result:
    """Evaluate a whole trace offline: all events are sorted first; the trace ends at its last instant, so
    windows closing by then are decided and only instances needing later instants are inconclusive."""
    monitor = Monitor(assertion, constants=constants, **options)
    monitor.ready.extend(sorted(events, key=_ts))
    violations = monitor.evaluate(final=True)
    violations += monitor.end_trace()
    violations.sort(key=lambda v: (v.time, v.instance_start))
    return monitor.result(violations)


# ===================================================================================================
# 5. Lossless migration (Fig. 3.43)
# ===================================================================================================


def migrate_begin(source: Monitor) -> None:
    """Step 2a at H1: take the monitor off the scheduler; it keeps buffering events."""
    source.suspended = True


def standby_copy(program: Program, **options: Any) -> Monitor:
    """Step 3 at H2: H2's copy of the monitor, subscribed and buffering, not scheduled."""
    m = Monitor(program, **options)
    m.suspended = True
    return m


def migrate_t0(destination: Monitor, force: bool = False) -> float | None:
    """Step 4 at H2: T0, once H2 holds enough events for its first sort (None until then).

    T0 is the oldest *complete* timestamp in H2's buffer: H2 may have subscribed in the middle of the
    events that share its oldest timestamp (ties are common in sampled traces), so T0 is the next distinct
    timestamp after it and H2's events before T0 are discarded at step 6 (H1 sends those). With the
    thesis's distinct PTP timestamps this only moves the cut by one event. Events must reach the handlers
    in timestamp order (up to the sort threshold), as the thesis assumes. ``force`` (the stream ended
    before H2 could sort) cuts at what H2 has, or at +inf: then H1 sends everything.
    """
    if destination.backlog < destination.sort_threshold and not force:
        return None
    stamps = sorted({e[2] for e in destination.raw} | {e[2] for e in destination.ready})
    if len(stamps) >= 2:
        return stamps[1]
    return float("inf") if force else None


def migrate_handover(source: Monitor, t0: float) -> dict:
    """Step 5 at H1: detach, and pack the not-yet-evaluated events with ts < T0 plus the monitor state.

    Events with ts < T0 travel compressed (one bit mask per instant, delta timestamps) with the held signal
    values as of the last of them; the pending instances travel as residual formulas. Events with
    ts >= T0 are dropped here: H2 has them.
    """
    source.detached = True
    if source.raw:
        source._sort()
    before = [e for e in source.ready if e[2] < t0]
    # the held values are those at the end of the already compressed instants; compress the rest after them
    instants, held = _compress(source.program, source.held, before, source.instant_mode)
    pre = [*source.pre, *instants]
    state = source.to_dict()
    state.update(held=held, pre=_pack_instants(pre), ready=[], raw=[], suspended=False, detached=False)
    state["counters"]["events"] += len(before)  # they are applied into the held values already
    source.ready.clear()
    source.pre.clear()
    return {"format": PAYLOAD_FORMAT, "t0": t0, "state": state}


def migrate_complete(destination: Monitor, payload: Mapping) -> None:
    """Step 6 at H2: restore the state, put H1's events ahead of its own buffer and schedule the monitor."""
    if payload.get("format") != PAYLOAD_FORMAT:
        raise InputError(f"not a {PAYLOAD_FORMAT} payload", field="format")
    t0 = payload["t0"]
    own = [e for e in sorted([*destination.ready, *destination.raw], key=_ts) if e[2] >= t0]
    destination._restore(payload["state"])
    destination.raw = []
    destination.ready = deque(own)
    destination.suspended = False
    destination.detached = False


# ===================================================================================================
# 6. Traces (the stl_check contract: a CSV with a time column and one column per signal)
# ===================================================================================================


def parse_trace_csv(text: str, source: str = "trace") -> tuple[list[Event], list[str]]:
    """Events of a CSV trace and its signal columns.

    The header names a ``time`` column (milliseconds) and one column per signal; each non-empty cell is an
    event (signal, value, time). Values are numbers or ``true``/``false``; an empty cell means the signal
    did not change at that row.
    """
    import csv
    import io

    rows = list(csv.reader(io.StringIO(text)))
    while rows and not any(cell.strip() for cell in rows[0]):
        rows.pop(0)
    if not rows:
        raise InputError(f"{source}: empty trace", field="trace")
    header = [h.strip() for h in rows[0]]
    if "time" not in header:
        raise InputError(f"{source}: line 1: no 'time' column (columns: {', '.join(header)})", field="trace")
    if not all(header):
        raise InputError(f"{source}: line 1: an empty column name", field="trace")
    twice = first_duplicate(header)
    if twice is not None:
        raise InputError(f"{source}: line 1: column {twice!r} appears twice", field="trace")
    t_col = header.index("time")
    signals = [h for h in header if h != "time"]
    events: list[Event] = []
    for line, row in enumerate(rows[1:], start=2):
        if not any(cell.strip() for cell in row):
            continue
        if len(row) != len(header):
            raise InputError(f"{source}: line {line}: {len(row)} cells for {len(header)} columns", field="trace")
        ts = _cell(row[t_col], source, line, "time")
        if ts is None or isinstance(ts, bool):
            raise InputError(f"{source}: line {line}: time must be a number, not {row[t_col]!r}", field="trace")
        for name, cell in zip(header, row, strict=True):
            if name != "time":
                value = _cell(cell, source, line, name)
                if value is not None:
                    events.append((name, value, ts))
    return events, signals


def _cell(cell: str, source: str, line: int, column: str) -> Any:
    text = cell.strip()
    if not text:
        return None
    low = text.lower()
    if low in ("true", "false"):
        return low == "true"
    try:
        return int(text)
    except ValueError:
        pass
    try:
        value = float(text)
    except ValueError:
        raise InputError(
            f"{source}: line {line}, column {column!r}: {text!r} is not a number or true/false", field="trace"
        ) from None
    if value != value or value in (float("inf"), float("-inf")):
        raise InputError(f"{source}: line {line}, column {column!r}: {text!r} is not a finite number", "trace")
    return value
