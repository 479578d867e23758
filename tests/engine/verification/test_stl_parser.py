"""The Fig. 3.40 assertion grammar (spec 03 §8.1, acceptance check 11) and the safe proposition evaluator."""

import random

import pytest

from continuum.engine.core.errors import InputError
from continuum.engine.verification.stl_parser import (
    Arith,
    Assertion,
    BoolOp,
    Cmp,
    Const,
    Eventually,
    HostBool,
    Next,
    Not,
    Num,
    Prop,
    Until,
    Var,
    compile_prop,
    parse_assertion,
    parse_formula,
    tokenize,
)

THESIS = [
    "G(speed > 0 -> F[0,5000](arrived))",
    "G((robot_x1 == x1 && robot_y1 == y1 && newGoal) -> F[0,timeout](robot_x2 == x2 && robot_y2 == y2))",
    "always(a -> next(b))",
]


@pytest.mark.parametrize("text", THESIS)
def test_thesis_assertions_parse(text):
    a = parse_assertion(text, constants={"timeout": 4000})
    assert isinstance(a, Assertion)
    assert parse_assertion(a.text(), constants={"timeout": 4000}) == a


def test_first_thesis_assertion_ast():
    a = parse_assertion(THESIS[0])
    assert a.interval is None
    assert a.antecedent == Prop(Cmp(">", Var("speed"), Num(0)))
    assert a.consequent == Eventually(0, 5000, Prop(Var("arrived")))


def test_navigation_assertion_substitutes_timeout():
    a = parse_assertion(THESIS[1], constants={"timeout": 4000})
    assert isinstance(a.consequent, Eventually) and a.consequent.hi == 4000
    # x1, y1, x2, y2 are signals unless given as constants too
    b = parse_assertion(THESIS[1], constants={"timeout": 4000, "x1": 1.5})
    assert "Var(name='x1')" not in repr(b.antecedent) and "Num(value=1.5)" in repr(b.antecedent)


def test_unknown_interval_name_is_an_error():
    with pytest.raises(InputError, match=r"column 56: .*'timeout' is not a defined constant"):
        parse_assertion(THESIS[1])


def test_implication_spellings_give_the_same_ast():
    assert parse_assertion("G(p |-> q)") == parse_assertion("G(p -> q)") == parse_assertion("G(p → q)")
    assert parse_assertion("always(a -> next(b))") == parse_assertion("G(a -> X(b))")
    assert parse_assertion("G(a -> eventually[0,5](b))") == parse_assertion("G(a -> F[0:5](b))")


def test_interval_on_g_is_optional_and_invariant_form():
    a = parse_assertion("G[0,10](x <= 9)")
    assert a.interval == (0, 10)
    assert a.antecedent == Const(True)
    assert a.consequent == Prop(Cmp("<=", Var("x"), Num(9)))


def test_precedence_or_xor_and_until():
    f = parse_formula("a || b xor c && d U[0,5] e")
    assert f == BoolOp(
        "||",
        Prop(Var("a")),
        BoolOp("xor", Prop(Var("b")), BoolOp("&&", Prop(Var("c")), Until("U", 0, 5, Prop(Var("d")), Prop(Var("e"))))),
    )
    assert parse_formula("!a && b") == BoolOp("&&", Not(Prop(Var("a"))), Prop(Var("b")))


def test_parenthesised_term_versus_subformula():
    assert parse_formula("(x + 1) * 2 > 3") == Prop(Cmp(">", Arith("*", Arith("+", Var("x"), Num(1)), Num(2)), Num(3)))
    assert parse_formula("(x > 1) && y") == BoolOp("&&", Prop(Cmp(">", Var("x"), Num(1))), Prop(Var("y")))
    assert parse_formula("X(b)") == Next(Prop(Var("b")))


def test_braced_host_expression_is_one_proposition():
    f = parse_formula("{a && !(b || c > 2)}")
    assert isinstance(f, Prop) and f.braced and isinstance(f.expr, HostBool)
    unbraced = parse_formula("a && b")
    assert isinstance(unbraced, BoolOp)


def test_operator_letters_are_signal_names_elsewhere():
    f = parse_formula("F > 2 && X && U")
    assert f == BoolOp("&&", BoolOp("&&", Prop(Cmp(">", Var("F"), Num(2))), Prop(Var("X"))), Prop(Var("U")))


def test_dotted_identifiers_are_signal_names():
    f = parse_formula("odom.pose.x >= -1.5")
    assert f == Prop(Cmp(">=", Var("odom.pose.x"), Num(-1.5)))


@pytest.mark.parametrize(
    ("text", "column", "expected"),
    [
        ("G(a -> F(b))", 9, "'[' (an interval"),
        ("G(a -> b U c)", 12, "'[' (an interval [lo,hi] is required after 'U')"),
        ("G(a -> b R c)", 12, "required after 'R'"),
        ("G(a -> F[0,](b))", 12, "non-negative number"),
        ("G(a -> F[0 5](b))", 12, "','"),
        ("G(a -> b", 9, "')' closing G"),
        ("G(a = b)", 5, "'=='"),
        ("F[0,1](a)", 1, "'G'"),
        ("G[5,3](a)", 2, "lo <= hi"),
        ("G(a -> b -> c)", 10, "only once"),
        ("G(3)", 4, "comparison operator"),
        ("G(a -> b) x", 11, "end of input"),
        ("G(a && )", 8, "a proposition"),
        ("G(f(x) > 1)", 3, "function calls are not allowed"),
        ("G(a U[0,1] b U[0,1] c)", 14, "U/R do not chain"),
        ("G(a -> G(b))", 8, "G may only appear once"),
    ],
)
def test_syntax_errors_name_column_and_expectation(text, column, expected):
    with pytest.raises(InputError) as info:
        parse_assertion(text)
    message = str(info.value)
    assert message.startswith(f"column {column}:"), message
    assert expected in message
    assert info.value.field == "assertion"


def test_empty_assertion():
    with pytest.raises(InputError, match="empty assertion"):
        parse_assertion("   ")


def test_tokenizer_columns():
    toks = tokenize("G(a |-> b)")
    assert [(t.value, t.col) for t in toks] == [("G", 1), ("(", 2), ("a", 3), ("|->", 5), ("b", 9), (")", 10), ("", 11)]


# ---- safe evaluator --------------------------------------------------------------------------------


def _prop(text):
    f = parse_formula(text)
    assert isinstance(f, Prop)
    return compile_prop(f)


def test_evaluator_comparisons_and_arithmetic():
    fn = _prop("(x + 1) * 2 > y / 4")
    assert fn({"x": 1, "y": 8}) is True
    assert fn({"x": 0, "y": 8}) is False


def test_unknown_signal_makes_comparison_false():
    assert _prop("speed > 10")({}) is False
    assert _prop("speed <= 10")({}) is False
    assert _prop("arrived")({}) is False


def test_division_by_zero_does_not_raise():
    assert _prop("x / y > 1")({"x": 1, "y": 0}) is True  # +inf
    assert _prop("x / y > 1")({"x": 0, "y": 0}) is False  # nan
    assert _prop("x / y < 0")({"x": -1, "y": 0}) is True


def test_incomparable_values_are_false():
    assert _prop("x > 1")({"x": "fast"}) is False
    assert _prop("x + 1 > 1")({"x": "fast"}) is False


def test_braced_boolean_logic():
    fn = _prop("{a && !(b || c > 2)}")
    assert fn({"a": True, "b": False, "c": 1}) is True
    assert fn({"a": True, "b": False, "c": 3}) is False
    assert fn({"a": True, "b": True, "c": 1}) is False


def test_boolean_signal_compared_with_literal():
    fn = _prop("arrived == true")
    assert fn({"arrived": True}) is True
    assert fn({"arrived": False}) is False


def test_no_python_eval_or_attributes():
    # Identifiers are dictionary keys, never Python names: builtins and dunder paths stay plain signals.
    assert _prop("__import__ > 1")({"__import__": 2}) is True
    assert _prop("open > 1")({}) is False
    # A dotted path is one dictionary key, not an attribute lookup on the value.
    assert _prop("x.__class__ > 1")({"x": 5}) is False
    assert _prop("x.__class__ > 1")({"x.__class__": 2}) is True


def _random_formula(rng, depth):
    atoms = ["a", "b", "x > 3", "y <= -2", "{a && x != 1}", "true", "(x + y) * 2 >= 7"]
    if depth == 0:
        return rng.choice(atoms)
    kind = rng.randrange(8)
    sub = lambda: _random_formula(rng, depth - 1)  # noqa: E731
    lo = rng.randrange(5)
    hi = lo + rng.randrange(5)
    return [
        lambda: f"!{sub()}",
        lambda: f"({sub()} && {sub()})",
        lambda: f"({sub()} || {sub()})",
        lambda: f"({sub()} xor {sub()})",
        lambda: f"F[{lo},{hi}]({sub()})",
        lambda: f"X({sub()})",
        lambda: f"(({sub()}) U[{lo},{hi}] ({sub()}))",
        lambda: f"(({sub()}) R[{lo},{hi}] ({sub()}))",
    ][kind]()


def test_printer_round_trips_random_formulas():
    rng = random.Random(7)
    for _ in range(300):
        text = f"G({_random_formula(rng, 3)} -> {_random_formula(rng, 3)})"
        a = parse_assertion(text)
        assert parse_assertion(a.text()) == a, text
