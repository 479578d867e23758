"""A direct, slow reference semantics of the assertion language, used as a test oracle.

It evaluates the parser's AST over the whole list of instants with the textbook definitions (spec 03 §8.2)
in three-valued logic: ``None`` means the finite trace does not decide the value yet. It shares only the
proposition evaluator with the monitor, not its progression machinery.
"""

from __future__ import annotations

from functools import cache

from continuum.engine.verification import stl_parser as P


def instants(events, mode="timestamp"):
    """Group sorted events into instants; returns [(ts, held values after the instant, last event)]."""
    out = []
    held = {}
    for e in sorted(events, key=lambda e: e[2]):
        held[e[0]] = e[1]
        if mode == "timestamp" and out and out[-1][0] == e[2]:
            out[-1] = (e[2], dict(held), e)
        else:
            out.append((e[2], dict(held), e))
    return out


def _and(a, b):
    if a is False or b is False:
        return False
    if a is None or b is None:
        return None
    return True


def _or(a, b):
    if a is True or b is True:
        return True
    if a is None or b is None:
        return None
    return False


def _not(a):
    return None if a is None else not a


def make_sat(inst, inclusive=False, complete=False):
    """``complete``: the trace ends at its last instant (offline), so a window closing by then is decided."""
    n = len(inst)
    end = inst[-1][0] if inst else None
    compiled = {}

    @cache
    def sat(f, i):
        if isinstance(f, P.Const):
            return f.value
        if isinstance(f, P.Prop):
            if f not in compiled:
                compiled[f] = P.compile_prop(f)
            return compiled[f](inst[i][1])
        if isinstance(f, P.Not):
            return _not(sat(f.operand, i))
        if isinstance(f, P.BoolOp):
            a, b = sat(f.left, i), sat(f.right, i)
            if f.op == "&&":
                return _and(a, b)
            if f.op == "||":
                return _or(a, b)
            return None if a is None or b is None else a != b
        if isinstance(f, P.Next):
            return sat(f.operand, i + 1) if i + 1 < n else None
        if isinstance(f, P.Eventually):
            lo, hi = inst[i][0] + f.lo, inst[i][0] + f.hi
            value, closed = False, False
            for j in range(i, n):
                if inst[j][0] > hi:
                    closed = True
                    break
                if inst[j][0] >= lo:
                    value = _or(value, sat(f.operand, j))
            closed = closed or (complete and hi <= end)
            return value if (closed or value is True) else _or(value, None)
        if isinstance(f, P.Until):
            if f.op == "R":
                return _not(sat(P.Until("U", f.lo, f.hi, P.Not(f.left), P.Not(f.right)), i))
            lo, hi = inst[i][0] + f.lo, inst[i][0] + f.hi
            value, prefix, closed = False, True, False
            for j in range(i, n):
                if inst[j][0] > hi:
                    closed = True
                    break
                phi = sat(f.left, j)
                if inst[j][0] >= lo:
                    psi = sat(f.right, j)
                    value = _or(value, _and(prefix, _and(phi, psi) if inclusive else psi))
                prefix = _and(prefix, phi)
                if prefix is False:
                    closed = True
                    break
            closed = closed or (complete and hi <= end)
            return value if (closed or value is True) else _or(value, None)
        raise TypeError(f)

    return sat


def instance_verdicts(assertion: P.Assertion, events, mode="timestamp", inclusive=False, complete=False):
    """{start ts: True/False/None} for every instant in the G window (``complete``: see make_sat)."""
    inst = instants(events, mode)
    sat = make_sat(inst, inclusive, complete)
    out = {}
    if not inst:
        return out
    t0 = inst[0][0]
    lo, hi = assertion.interval if assertion.interval is not None else (0, float("inf"))
    for i, (ts, _, _) in enumerate(inst):
        if lo <= ts - t0 <= hi:
            out[ts] = _or(_not(sat(assertion.antecedent, i)), sat(assertion.consequent, i))
    return out
