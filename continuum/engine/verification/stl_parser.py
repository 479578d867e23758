"""Parser for the assertion language of thesis §3.5, Fig. 3.40 (spec 03 §8.1).

Grammar (EBNF; precedence and associativity are the spec's proposal, Fig. 3.40 itself is flat)::

    assertion   = ("G" | "always") [interval] "(" tformula [implies tformula] ")" ;
    implies     = "|->" | "->" | "→" ;
    interval    = "[" bound ("," | ":") bound "]" ;            (* milliseconds, lo <= hi *)
    tformula    = xor_f { "||" xor_f } ;
    xor_f       = and_f { "xor" and_f } ;
    and_f       = until_f { "&&" until_f } ;
    until_f     = unary [ ("U" | "R") interval unary ] ;       (* non-associative *)
    unary       = "!" unary
                | ("F" | "eventually") interval "(" tformula ")"
                | ("X" | "next") "(" tformula ")"             (* extension: Fig. 3.44 uses it *)
                | "(" tformula ")"
                | proposition ;
    proposition = "{" host_or "}" | term relop term | identifier | "true" | "false" ;
    host_or     = host_and { "||" host_and } ;   host_and = host_not { "&&" host_not } ;
    host_not    = "!" host_not | term [relop term] ;
    term        = product { ("+" | "-") product } ;   product = factor { ("*" | "/") factor } ;
    factor      = "-" factor | number | identifier | "true" | "false" | "(" term ")" ;
                  (* inside braces "(" host_or ")" *)
    identifier  = name { "." name } ;                          (* a signal, e.g. odom.pose.x *)

Readings taken where the thesis is silent (spec 03 §15):
  * #15 ``X``/``next`` and ``always`` are accepted as extensions.
  * #16 precedence as above; a C-like boolean host expression goes in braces ``{a && b}`` and becomes ONE
    proposition (one placeholder), whereas ``a && b`` outside braces is a formula over two propositions.
  * #20 the interval of ``G`` is optional; omitted means the whole run.
  * ``G(φ)`` without an implication is read as ``G(true -> φ)`` (an invariant), so ``G[0,10](x <= 9)``
    works as in rtamt.
  * Names listed in ``constants`` are replaced by their number wherever they appear (interval bounds and
    terms), e.g. ``timeout`` in the thesis's navigation assertion.
  * ``F``, ``X``, ``U``, ``R``, ``G`` are operators only where an operator can stand (``F[``, ``X(``, ``a U[``);
    elsewhere they are ordinary signal names.

Propositions are evaluated by :func:`compile_expr`, a closure compiler over this module's own AST: no
Python ``eval``, no attribute access (a dotted identifier is one signal name, not an attribute lookup).
Every syntax error raises :class:`~continuum.engine.core.errors.InputError` naming the column and what was
expected.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields
from typing import Any, cast

from continuum.engine.core import limits
from continuum.engine.core.errors import InputError

__all__ = [
    "Arith",
    "Assertion",
    "BoolLit",
    "BoolOp",
    "Cmp",
    "Const",
    "Eventually",
    "Expr",
    "Formula",
    "HostBool",
    "HostNot",
    "Neg",
    "Next",
    "Not",
    "Num",
    "Prop",
    "Token",
    "Until",
    "Values",
    "Var",
    "compile_expr",
    "compile_prop",
    "parse_assertion",
    "parse_formula",
    "tokenize",
    "variables",
]

# ---------------------------------------------------------------------------------------------------
# AST: host expressions (the propositions' insides)
# ---------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Num:
    value: float

    def text(self) -> str:
        return _num(self.value)


@dataclass(frozen=True)
class BoolLit:
    value: bool

    def text(self) -> str:
        return "true" if self.value else "false"


@dataclass(frozen=True)
class Var:
    name: str

    def text(self) -> str:
        return self.name


@dataclass(frozen=True)
class Neg:
    operand: Expr

    def text(self) -> str:
        return f"-{_wrap(self.operand, _ATOM)}"


@dataclass(frozen=True)
class Arith:
    op: str  # + - * /
    left: Expr
    right: Expr

    def text(self) -> str:
        level = _HLEVEL[self.op]
        return f"{_wrap(self.left, level)} {self.op} {_wrap(self.right, level + 1)}"


@dataclass(frozen=True)
class Cmp:
    op: str  # == != < <= > >=
    left: Expr
    right: Expr

    def text(self) -> str:
        return f"{_wrap(self.left, _HLEVEL['+'])} {self.op} {_wrap(self.right, _HLEVEL['+'])}"


@dataclass(frozen=True)
class HostNot:
    operand: Expr

    def text(self) -> str:
        return f"!{_wrap(self.operand, _HLEVEL['!'])}"


@dataclass(frozen=True)
class HostBool:
    op: str  # && ||
    left: Expr
    right: Expr

    def text(self) -> str:
        level = _HLEVEL[self.op]
        return f"{_wrap(self.left, level)} {self.op} {_wrap(self.right, level + 1)}"


Expr = Num | BoolLit | Var | Neg | Arith | Cmp | HostNot | HostBool

# Binding strength of host-expression nodes, loosest first (used to print with minimal parentheses).
_HLEVEL = {"||": 1, "&&": 2, "!": 3, "cmp": 4, "+": 5, "-": 5, "*": 6, "/": 6, "neg": 7}
_ATOM = 9


def _level(e: Expr) -> int:
    if isinstance(e, (Arith, HostBool)):
        return _HLEVEL[e.op]
    if isinstance(e, Cmp):
        return _HLEVEL["cmp"]
    if isinstance(e, HostNot):
        return _HLEVEL["!"]
    if isinstance(e, Neg):
        return _HLEVEL["neg"]
    if isinstance(e, Num) and e.value < 0:
        return _HLEVEL["neg"]
    return _ATOM


def _wrap(e: Expr, min_level: int) -> str:
    """Parenthesise ``e`` when it binds looser than its context needs (for faithful re-printing)."""
    return e.text() if _level(e) >= min_level else f"({e.text()})"


# ---------------------------------------------------------------------------------------------------
# AST: temporal formulas
# ---------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Prop:
    """An atomic proposition: becomes one boolean placeholder in the monitor (Fig. 3.41)."""

    expr: Expr
    braced: bool = False

    def text(self) -> str:
        return "{" + self.expr.text() + "}" if self.braced else self.expr.text()


@dataclass(frozen=True)
class Const:
    value: bool

    def text(self) -> str:
        return "true" if self.value else "false"


@dataclass(frozen=True)
class Not:
    operand: Formula

    def text(self) -> str:
        return f"!{_fwrap(self.operand, 9)}"


@dataclass(frozen=True)
class BoolOp:
    op: str  # "&&", "||", "xor"
    left: Formula
    right: Formula

    def text(self) -> str:
        lvl = _FLEVEL[self.op]
        return f"{_fwrap(self.left, lvl)} {self.op} {_fwrap(self.right, lvl + 1)}"


@dataclass(frozen=True)
class Eventually:
    lo: float
    hi: float
    operand: Formula

    def text(self) -> str:
        return f"F[{_num(self.lo)},{_num(self.hi)}]({self.operand.text()})"


@dataclass(frozen=True)
class Next:
    operand: Formula

    def text(self) -> str:
        return f"X({self.operand.text()})"


@dataclass(frozen=True)
class Until:
    op: str  # "U" or "R"
    lo: float
    hi: float
    left: Formula
    right: Formula

    def text(self) -> str:
        return f"{_fwrap(self.left, 9)} {self.op}[{_num(self.lo)},{_num(self.hi)}] {_fwrap(self.right, 9)}"


Formula = Prop | Const | Not | BoolOp | Eventually | Next | Until

_FLEVEL = {"||": 1, "xor": 2, "&&": 3}


def _fwrap(f: Formula, min_level: int) -> str:
    if isinstance(f, BoolOp):
        own = _FLEVEL[f.op]
    elif isinstance(f, Until):
        own = 4
    elif isinstance(f, Prop) and not f.braced and _level(f.expr) < _ATOM:
        own = 5  # a comparison binds tighter than every formula operator, but not than "!"
    else:
        own = 9
    return f.text() if own >= min_level else f"({f.text()})"


def _num(v: float) -> str:
    v = float(v)
    return str(int(v)) if v.is_integer() and abs(v) < 1e15 else repr(v)


@dataclass(frozen=True)
class Assertion:
    """``G[lo,hi](antecedent -> consequent)``; ``interval`` is None for the whole run."""

    interval: tuple[float, float] | None
    antecedent: Formula
    consequent: Formula
    source: str = field(default="", compare=False)

    def text(self) -> str:
        iv = "" if self.interval is None else f"[{_num(self.interval[0])},{_num(self.interval[1])}]"
        return f"G{iv}({self.antecedent.text()} -> {self.consequent.text()})"


# ---------------------------------------------------------------------------------------------------
# Tokenizer
# ---------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Token:
    kind: str  # "num", "name", "op", "end"
    value: str
    col: int  # 1-based column

    def show(self) -> str:
        return "end of input" if self.kind == "end" else repr(self.value)


_TOKEN_RE = re.compile(
    r"""
    (?P<ws>\s+)
  | (?P<num>(?:\d+\.\d*|\.\d+|\d+)(?:[eE][+-]?\d+)?)
  | (?P<name>[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*)
  | (?P<op>\|->|->|→|&&|\|\||==|!=|<=|>=|[!<>()\[\]{},:+\-*/])
    """,
    re.VERBOSE,
)


def tokenize(text: str) -> list[Token]:
    tokens: list[Token] = []
    pos = 0
    while pos < len(text):
        m = _TOKEN_RE.match(text, pos)
        if m is None:
            ch = text[pos]
            hint = " (use '==' to compare)" if ch == "=" else " (use '||')" if ch == "|" else ""
            hint = hint or (" (use '&&')" if ch == "&" else "")
            raise InputError(f"column {pos + 1}: unexpected character {ch!r}{hint}", field="assertion")
        kind = m.lastgroup
        assert kind is not None  # every alternative of _TOKEN_RE is a named group
        if kind != "ws":
            tokens.append(Token(kind, m.group(), pos + 1))
        pos = m.end()
    tokens.append(Token("end", "", len(text) + 1))
    return tokens


# ---------------------------------------------------------------------------------------------------
# Parser
# ---------------------------------------------------------------------------------------------------


class _Fail(Exception):
    """Internal: a syntax error at a column; the furthest one wins when alternatives are tried."""

    def __init__(self, col: int, expected: str, found: str):
        super().__init__(f"column {col}: expected {expected}, found {found}")
        self.col = col


_RELOPS = {"==", "!=", "<", "<=", ">", ">="}
_IMPLIES = {"|->", "->", "→"}
_EVENTUALLY = {"F", "eventually"}
_NEXT = {"X", "next"}
_ALWAYS = {"G", "always"}


class _TooDeep(Exception):
    """Nesting past ``limits.stl_depth``."""


class _Parser:
    def __init__(self, text: str, constants: Mapping[str, float]):
        self.text = text
        self.toks = tokenize(text)
        self.i = 0
        self.constants = dict(constants)
        self.depth = 0  # recursion depth of the descent, bounded by limits.stl_depth

    def enter(self) -> None:
        """Count one level of nesting; past the limit the assertion is refused (no RecursionError)."""
        self.depth += 1
        if self.depth > limits.get().stl_depth:
            raise _TooDeep()

    # -- token helpers ---------------------------------------------------------------------------
    @property
    def tok(self) -> Token:
        return self.toks[self.i]

    def peek(self, k: int = 1) -> Token:
        return self.toks[min(self.i + k, len(self.toks) - 1)]

    def at(self, *values: str) -> bool:
        t = self.tok
        return t.kind in ("op", "name") and t.value in values

    def fail(self, expected: str) -> _Fail:
        return _Fail(self.tok.col, expected, self.tok.show())

    def expect(self, value: str, expected: str | None = None) -> Token:
        if not self.at(value):
            raise self.fail(expected or repr(value))
        t = self.tok
        self.i += 1
        return t

    # -- assertion -------------------------------------------------------------------------------
    def assertion(self) -> Assertion:
        if not (self.tok.kind == "name" and self.tok.value in _ALWAYS):
            raise self.fail("'G' (or 'always') starting the assertion")
        self.i += 1
        interval = self.interval() if self.at("[") else None
        self.expect("(", "'(' after G")
        first = self.tformula()
        if self.at(*_IMPLIES):
            self.i += 1
            antecedent, consequent = first, self.tformula()
        else:
            antecedent, consequent = Const(True), first
        if self.at(*_IMPLIES):
            raise self.fail("')' (an implication may appear only once, at the top of G(...))")
        self.expect(")", "')' closing G(...)")
        if self.tok.kind != "end":
            raise self.fail("end of input after the assertion")
        return Assertion(interval, antecedent, consequent, source=self.text)

    def interval(self) -> tuple[float, float]:
        start = self.expect("[", "'[' (an interval [lo,hi] in milliseconds)")
        lo = self.bound()
        if not self.at(",", ":"):
            raise self.fail("',' between the interval bounds")
        self.i += 1
        hi = self.bound()
        self.expect("]", "']' closing the interval")
        if lo > hi:
            raise _Fail(start.col, f"an interval with lo <= hi, not [{_num(lo)},{_num(hi)}]", "lo > hi")
        return lo, hi

    def bound(self) -> float:
        t = self.tok
        if t.kind == "num":
            self.i += 1
            return float(t.value)
        if t.kind == "name" and t.value in self.constants:
            self.i += 1
            value = float(self.constants[t.value])
            if value < 0:
                raise _Fail(t.col, f"a non-negative bound ({t.value} = {_num(value)})", repr(t.value))
            return value
        if t.kind == "name":
            raise self.fail(f"a number of milliseconds ({t.value!r} is not a defined constant)")
        raise self.fail("a non-negative number of milliseconds")

    # -- temporal formulas -----------------------------------------------------------------------
    def tformula(self) -> Formula:
        left = self.xor_f()
        while self.at("||"):
            self.i += 1
            left = BoolOp("||", left, self.xor_f())
        return left

    def xor_f(self) -> Formula:
        left = self.and_f()
        while self.tok.kind == "name" and self.tok.value == "xor":
            self.i += 1
            left = BoolOp("xor", left, self.and_f())
        return left

    def and_f(self) -> Formula:
        left = self.until_f()
        while self.at("&&"):
            self.i += 1
            left = BoolOp("&&", left, self.until_f())
        return left

    def until_f(self) -> Formula:
        left = self.unary()
        if self.tok.kind == "name" and self.tok.value in ("U", "R"):
            op = self.tok.value
            self.i += 1
            if not self.at("["):
                raise self.fail(f"'[' (an interval [lo,hi] is required after '{op}')")
            lo, hi = self.interval()
            right = self.unary()
            if self.tok.kind == "name" and self.tok.value in ("U", "R"):
                raise self.fail("a closing operator (U/R do not chain: add parentheses)")
            return Until(op, lo, hi, left, right)
        return left

    def unary(self) -> Formula:
        self.enter()
        try:
            return self._unary()
        finally:
            self.depth -= 1

    def _unary(self) -> Formula:
        t = self.tok
        if self.at("!"):
            self.i += 1
            return Not(self.unary())
        if t.kind == "name" and t.value in _EVENTUALLY and self.peek().value in ("[", "("):
            self.i += 1
            if not self.at("["):
                raise self.fail(f"'[' (an interval [lo,hi] is required after '{t.value}')")
            lo, hi = self.interval()
            self.expect("(", f"'(' after {t.value}[..]")
            inner = self.tformula()
            self.expect(")", f"')' closing {t.value}(...)")
            return Eventually(lo, hi, inner)
        if t.kind == "name" and t.value in _NEXT and self.peek().value == "(":
            self.i += 2
            inner = self.tformula()
            self.expect(")", f"')' closing {t.value}(...)")
            return Next(inner)
        if t.kind == "name" and t.value in _ALWAYS and self.peek().value in ("[", "("):
            raise self.fail("a formula (G may only appear once, at the top of the assertion)")
        if self.at("("):
            return self.parenthesised()
        return self.proposition()

    def parenthesised(self) -> Formula:
        """``(`` starts either an arithmetic term of a comparison or a sub-formula: try both."""
        save = self.i
        try:
            return self.comparison()
        except _Fail as as_term:
            self.i = save
            try:
                self.expect("(")
                inner = self.tformula()
                self.expect(")", "')'")
                return inner
            except _Fail as as_formula:
                raise as_term if as_term.col > as_formula.col else as_formula from None

    def proposition(self) -> Formula:
        t = self.tok
        if self.at("{"):
            self.i += 1
            expr = self.host_or()
            self.expect("}", "'}' closing the braced expression")
            return Prop(expr, braced=True)
        if t.kind == "name" and t.value in ("true", "false") and self.peek().value not in _RELOPS:
            self.i += 1
            return Const(t.value == "true")
        if t.kind in ("name", "num") or self.at("-", "("):
            return self.comparison()
        raise self.fail("a proposition (a comparison, a signal name, true/false or {expression})")

    def comparison(self) -> Formula:
        left = self.term()
        if self.tok.kind == "op" and self.tok.value in _RELOPS:
            op = self.tok.value
            self.i += 1
            return Prop(Cmp(op, left, self.term()))
        if isinstance(left, Var):
            return Prop(left)  # a boolean signal used as a proposition
        raise self.fail("a comparison operator (==, !=, <, <=, >, >=)")

    # -- host expressions ------------------------------------------------------------------------
    def host_or(self) -> Expr:
        left = self.host_and()
        while self.at("||"):
            self.i += 1
            left = HostBool("||", left, self.host_and())
        return left

    def host_and(self) -> Expr:
        left = self.host_not()
        while self.at("&&"):
            self.i += 1
            left = HostBool("&&", left, self.host_not())
        return left

    def host_not(self) -> Expr:
        self.enter()
        try:
            return self._host_not()
        finally:
            self.depth -= 1

    def _host_not(self) -> Expr:
        if self.at("!"):
            self.i += 1
            return HostNot(self.host_not())
        left = self.term(braced=True)
        if self.tok.kind == "op" and self.tok.value in _RELOPS:
            op = self.tok.value
            self.i += 1
            return Cmp(op, left, self.term(braced=True))
        return left

    def term(self, braced: bool = False) -> Expr:
        left = self.product(braced)
        while self.at("+", "-"):
            op = self.tok.value
            self.i += 1
            left = Arith(op, left, self.product(braced))
        return left

    def product(self, braced: bool) -> Expr:
        left = self.factor(braced)
        while self.at("*", "/"):
            op = self.tok.value
            self.i += 1
            left = Arith(op, left, self.factor(braced))
        return left

    def factor(self, braced: bool) -> Expr:
        self.enter()
        try:
            return self._factor(braced)
        finally:
            self.depth -= 1

    def _factor(self, braced: bool) -> Expr:
        t = self.tok
        if self.at("-"):
            self.i += 1
            inner = self.factor(braced)
            return Num(-inner.value) if isinstance(inner, Num) else Neg(inner)
        if t.kind == "num":
            self.i += 1
            return Num(_number(t.value))
        if t.kind == "name":
            self.i += 1
            if t.value in ("true", "false"):
                return BoolLit(t.value == "true")
            if t.value in self.constants:
                return Num(self.constants[t.value])
            if self.at("("):
                raise _Fail(t.col, "an operator after a signal name (function calls are not allowed)", t.show())
            return Var(t.value)
        if self.at("("):
            self.i += 1
            inner = self.host_or() if braced else self.term()
            self.expect(")", "')'")
            return inner
        raise self.fail("a number, a signal name or '('")


def _number(text: str) -> float:
    return int(text) if text.isdigit() else float(text)


def parse_assertion(text: str, constants: Mapping[str, float] | None = None) -> Assertion:
    """Parse one assertion of the Fig. 3.40 grammar; raise InputError with the column on a syntax error."""
    if not text or not text.strip():
        raise InputError("empty assertion", field="assertion")
    _check_length(text)
    parser = _Parser(text, constants or {})
    try:
        return _check_depth(parser.assertion())
    except _Fail as exc:
        raise InputError(str(exc), field="assertion") from None
    except _TooDeep:
        raise _too_deep() from None


def parse_formula(text: str, constants: Mapping[str, float] | None = None) -> Formula:
    """Parse a bare temporal formula (no ``G``); handy for tests and for consequents built by tools."""
    _check_length(text)
    parser = _Parser(text, constants or {})
    try:
        f = parser.tformula()
        if parser.tok.kind != "end":
            raise parser.fail("end of input")
        return _check_depth(f)
    except _Fail as exc:
        raise InputError(str(exc), field="assertion") from None
    except _TooDeep:
        raise _too_deep() from None


def _check_length(text: str) -> None:
    limit = limits.get().stl_length
    if len(text) > limit:
        raise InputError(f"assertion: at most {limit} characters (got {len(text)})", field="assertion")


def _too_deep() -> InputError:
    return InputError(f"assertion: at most {limits.get().stl_depth} levels of nesting", field="assertion")


def _check_depth(node):
    """Refuse an AST deeper than ``limits.stl_depth`` (long operator chains nest too: ``a && b && c`` is
    two levels), so that printing, compiling and monitoring it, all recursive, stay far from Python's
    recursion limit. Iterative."""
    limit = limits.get().stl_depth
    stack = [(node, 0)]
    while stack:
        n, depth = stack.pop()
        if depth > limit:
            raise _too_deep()
        for f in fields(n) if hasattr(n, "__dataclass_fields__") else ():
            child = getattr(n, f.name)
            if hasattr(child, "__dataclass_fields__"):
                stack.append((child, depth + 1))
    return node


# ---------------------------------------------------------------------------------------------------
# The safe evaluator: closures over our own AST
# ---------------------------------------------------------------------------------------------------

Values = Mapping[str, object]


def variables(node: Expr | Formula | Assertion) -> set[str]:
    """The signal names a node reads."""
    out: set[str] = set()

    def walk(n) -> None:
        if isinstance(n, Var):
            out.add(n.name)
        for name in getattr(n, "__dataclass_fields__", {}):
            child = getattr(n, name)
            if hasattr(child, "__dataclass_fields__"):
                walk(child)

    walk(node)
    return out


def _cmp(op: str) -> Callable[[Any, Any], Any]:
    import operator

    fn = {"==": operator.eq, "!=": operator.ne, "<": operator.lt, "<=": operator.le, ">": operator.gt}.get(op)
    return fn or operator.ge


def _div(a, b):
    try:
        return a / b
    except ZeroDivisionError:
        return math.nan if a == 0 else math.copysign(math.inf, a) * math.copysign(1, b)


_ARITH = {"+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b, "/": _div}


def compile_expr(e: Expr) -> Callable[[Values], object]:
    """Compile an expression into a closure ``values -> value``.

    An unknown signal (no event yet) reads as ``None``; arithmetic on ``None`` gives ``None`` and a
    comparison involving ``None`` (or values of incomparable types) is false, so a proposition over a
    signal never seen is false, as in the Fig. 3.41 example (``speed > 10`` is 0 before any speed).
    """
    if isinstance(e, Num):
        v = e.value
        return lambda values: v
    if isinstance(e, BoolLit):
        b = e.value
        return lambda values: b
    if isinstance(e, Var):
        name = e.name
        return lambda values: values.get(name)
    if isinstance(e, Neg):
        f = compile_expr(e.operand)

        def neg(values):
            v = f(values)
            return -v if isinstance(v, (int, float)) else None  # None and strings have no negation

        return neg
    if isinstance(e, Arith):
        return _compile_arith(e)
    if isinstance(e, Cmp):
        return _compile_cmp(e)
    if isinstance(e, HostNot):
        f = compile_expr(e.operand)
        return lambda values: not _truth(f(values))
    if isinstance(e, HostBool):
        fl, fr = compile_expr(e.left), compile_expr(e.right)
        if e.op == "&&":
            return lambda values: _truth(fl(values)) and _truth(fr(values))
        return lambda values: _truth(fl(values)) or _truth(fr(values))
    raise TypeError(f"not an expression node: {e!r}")


def _compile_arith(e: Arith) -> Callable[[Values], object]:
    fl, fr, fn = compile_expr(e.left), compile_expr(e.right), _ARITH[e.op]

    def arith(values):
        a, b = fl(values), fr(values)
        if a is None or b is None:
            return None
        try:
            return fn(a, b)
        except TypeError:
            return None

    return arith


def _compile_cmp(e: Cmp) -> Callable[[Values], bool]:
    fn = _cmp(e.op)
    left, right = e.left, e.right
    # Fast path for the common "signal relop number" proposition.
    if isinstance(left, Var) and isinstance(right, Num):
        name, k = left.name, right.value

        def var_num(values):
            v = values.get(name)
            if v is None:
                return False
            try:
                return fn(v, k)
            except TypeError:
                return False

        return var_num
    fl, fr = compile_expr(left), compile_expr(right)

    def cmp(values):
        a, b = fl(values), fr(values)
        if a is None or b is None:
            return False
        try:
            return bool(fn(a, b))
        except TypeError:
            return False

    return cmp


def _truth(v: object) -> bool:
    return False if v is None else bool(v)


def compile_prop(p: Prop) -> Callable[[Values], bool]:
    """The evaluation closure of one proposition (always returns a bool)."""
    f = compile_expr(p.expr)
    if isinstance(p.expr, (Cmp, HostNot, HostBool)):
        return cast(Callable[[Values], bool], f)  # these expressions evaluate to a bool
    return lambda values: _truth(f(values))
