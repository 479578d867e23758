"""Verdicts agree with rtamt (an established STL monitor) on generated sampled traces.

rtamt computes robustness on discrete time; its sign is the Boolean verdict of the formula at each sample.
Our monitor reports one instance per sample (an instant = a timestamp; every sample updates every signal
at ts = sample index in ms, so rtamt's sample-counted intervals equal our millisecond intervals). Samples
whose window reaches past the end of the trace are skipped: rtamt's offline semantics counts a truncated
window as false, ours reports the instance as pending (inconclusive).

rtamt's ``xor`` robustness is not a Boolean xor (xor of two true inputs is positive) and it has no bounded
release; R is compared through its definition ``!(!a U !b)``.
"""

import random

import pytest

from continuum.engine.verification.stl_monitor import Monitor

rtamt = pytest.importorskip("rtamt")

# (our assertion, rtamt formula, horizon in samples)
FAMILY = [
    ("G(x >= 7 -> F[0,{b}](y >= 7))", "(x>=7) -> (eventually[0:{b}](y>=7))", "{b}"),
    ("G(x <= 9)", "x<=9", "0"),
    ("G(x >= 7 -> X(y >= 7))", "(x>=7) -> (next(y>=7))", "1"),
    ("G(x >= 7 -> (y >= 3) U[1,{b}] (z >= 7))", "(x>=7) -> ((y>=3) until[1:{b}] (z>=7))", "{b}"),
    ("G(x >= 2 -> (y >= 3) R[0,{b}] (z >= 1))", "(x>=2) -> (not((not(y>=3)) until[0:{b}] (not(z>=1))))", "{b}"),
    (
        "G(F[0,3](x >= 8) -> F[2,{b}](y >= 6 && z < 5))",
        "(eventually[0:3](x>=8)) -> (eventually[2:{b}]((y>=6) and (z<5)))",
        "{b}",
    ),
    ("G(!(x >= 5) || y < 3 && X(z > 4))", "(not(x>=5)) or ((y<3) and next(z>4))", "1"),
]


def _walk(rng, n):
    """A random walk in [0, 10]: signals linger above or below a threshold, so windows both pass and fail."""
    v, out = rng.uniform(0, 10), []
    for _ in range(n):
        v = min(10.0, max(0.0, v + rng.uniform(-1.5, 1.5)))
        out.append(v)
    return out


def _trace(rng, n):
    return {v: _walk(rng, n) for v in ("x", "y", "z")}


def _rtamt_verdicts(formula, data, n):
    spec = rtamt.StlDiscreteTimeSpecification()
    for v in data:
        spec.declare_var(v, "float")
    spec.spec = formula
    spec.parse()
    rob = spec.evaluate({"time": list(range(n)), **data})
    return [r >= 0 for _, r in rob]


def _our_verdicts(assertion, data, n):
    m = Monitor(assertion)
    for i in range(n):
        for v, values in data.items():
            m.push(v, values[i], i)
    violations = m.evaluate() + m.flush()
    failed = {v.instance_start for v in violations}
    pending = set(m.pending_starts())
    return [None if i in pending else i not in failed for i in range(n)]


@pytest.mark.parametrize(("ours", "theirs", "horizon"), FAMILY)
@pytest.mark.parametrize("b", [3, 10])
def test_verdicts_match_rtamt(ours, theirs, horizon, b):
    rng = random.Random(b * 31 + len(ours))
    n = 1000
    data = _trace(rng, n)
    h = int(horizon.format(b=b))
    # rtamt's horizon for nested windows is the sum of the windows; ours may decide earlier
    if "F[0,3](" in ours:
        h += 3
    want = _rtamt_verdicts(theirs.format(b=b), data, n)
    got = _our_verdicts(ours.format(b=b), data, n)
    compared = 0
    for i in range(n - h - 1):
        assert got[i] is not None, (i, "pending although the window closed")
        assert got[i] == want[i], (ours, i)
        compared += 1
    assert compared > 300 and 0 < sum(not w for w in want[: n - h - 1]) < compared
