"""The stl_check and allocate_monitors management commands (CONTRACTS.md).

The commands are driven through their classes (``call_command`` accepts a command object and
``run_from_argv`` gives the real exit status), so they work before the app is in INSTALLED_APPS.
"""

import json
from io import StringIO
from pathlib import Path

import pytest
from django.core.management import call_command

from apps.verification.management.commands import allocate_monitors, stl_check

DATA = Path(__file__).resolve().parents[1] / "data" / "verification"
TRACE = str(DATA / "speed_trace.csv")
STATS = str(DATA / "case_study_1.monitorstats.json")
SPEED = "G(speed > 0 -> F[0,5000](arrived))"


def _json(command, *args):
    out = StringIO()
    call_command(command, *args, "--json", stdout=out)
    return json.loads(out.getvalue())


def _exit(command, name, *args, capsys):
    command.requires_system_checks = []  # the project's URLconf is not needed to run an engine command
    with pytest.raises(SystemExit) as info:
        command.run_from_argv(["manage.py", name, *args])
    return info.value.code, capsys.readouterr()


def test_stl_check_reports_the_violation_with_its_time():
    result = _json(stl_check.Command(), TRACE, "--assertion", SPEED)
    assert result["verdict"] == "fail"
    assert result["violations"] == [{"time": 6001, "instance_start": 1000, "event": ["arrived", True, 6001]}]
    assert result["events"] == 10 and result["instants"] == 7
    assert result["skeleton"] == "G(p0 -> F[0,5000](p1))"
    assert result["placeholders"] == {"p0": "speed > 0", "p1": "arrived"}


def test_stl_check_pass_and_inconclusive():
    assert _json(stl_check.Command(), TRACE, "--assertion", "G(speed < 10)")["verdict"] == "pass"
    result = _json(stl_check.Command(), TRACE, "--assertion", "G(speed > 2 -> F[0,t](arrived))", "--const", "t=9000")
    assert result["verdict"] == "pass"
    result = _json(stl_check.Command(), TRACE, "--assertion", "G(speed >= 0 -> X(arrived))")
    assert result["verdict"] == "fail" and result["pending"] == 1  # the last row has no next instant


def test_stl_check_decides_a_window_closing_at_the_last_timestamp(tmp_path):
    """Every instant of F[0,3] from t=0 is in the trace (t = 0..3): the window is decided, not pending."""
    path = tmp_path / "x.csv"
    path.write_text("time,x\n0,1\n1,2\n2,3\n3,4\n")
    result = _json(stl_check.Command(), str(path), "--assertion", "G[0,0](F[0,3](x > 5))")
    assert result["verdict"] == "fail" and result["pending"] == 0
    assert result["violations"] == [{"time": 3, "instance_start": 0, "event": None}]
    assert _json(stl_check.Command(), str(path), "--assertion", "G[0,0](F[0,3](x > 3))")["verdict"] == "pass"
    assert _json(stl_check.Command(), str(path), "--assertion", "G[0,0](F[0,4](x > 5))")["verdict"] == "inconclusive"


def test_stl_check_signal_free_propositions(tmp_path):
    path = tmp_path / "b.csv"
    path.write_text("time,x,b\n0,1,\n1,2,\n2,3,4\n")
    assert _json(stl_check.Command(), str(path), "--assertion", "G({!(b > 5)})")["verdict"] == "pass"
    assert _json(stl_check.Command(), str(path), "--assertion", "G(1 < 2)")["verdict"] == "pass"
    assert _json(stl_check.Command(), str(path), "--assertion", "G(L > 2)", "--const", "L=3")["verdict"] == "pass"


def test_stl_check_human_summary():
    out = StringIO()
    call_command(stl_check.Command(), TRACE, "--assertion", SPEED, stdout=out)
    text = out.getvalue()
    assert text.startswith("fail: 1 violation(s) over 10 events")
    assert "t=6001: instance started at t=1000 failed" in text


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--assertion", "G(speed > 0 -> F(arrived))"], "column 17: expected '['"),
        (["--assertion", "G(speed > 0 -> F[0,5000](parked))"], "signal 'parked' used by the assertion"),
        (["--assertion", "G(speed > 0 -> F[0,t](arrived))"], "'t' is not a defined constant"),
        (["--assertion", "G(a)", "--const", "t:5"], "expected NAME=VALUE"),
    ],
)
def test_stl_check_bad_input_exits_2_with_one_line(args, message, capsys):
    code, captured = _exit(stl_check.Command(), "stl_check", TRACE, *args, capsys=capsys)
    assert code == 2
    assert message in captured.err
    assert captured.err.strip().count("\n") == 0 and "Traceback" not in captured.err


@pytest.mark.parametrize(
    ("csv", "message"),
    [
        ("t,speed\n0,1\n", "no 'time' column"),
        ("time,speed\n0,fast\n", "line 2, column 'speed': 'fast' is not a number"),
        ("time,speed\nnow,1\n", "line 2, column 'time': 'now' is not a number"),
        ("time,speed\ntrue,1\n", "line 2: time must be a number"),
        ("time,speed\n0,1,2\n", "line 2: 3 cells for 2 columns"),
        ("time,speed,speed\n0,1,2\n", "column 'speed' appears twice"),
        ("", "empty trace"),
    ],
)
def test_stl_check_bad_trace(tmp_path, csv, message, capsys):
    path = tmp_path / "trace.csv"
    path.write_text(csv)
    code, captured = _exit(stl_check.Command(), "stl_check", str(path), "--assertion", "G(speed > 0)", capsys=capsys)
    assert code == 2 and message in captured.err


def test_stl_check_missing_file(capsys):
    code, captured = _exit(stl_check.Command(), "stl_check", "/nope.csv", "--assertion", "G(a)", capsys=capsys)
    assert code == 2 and "no such file" in captured.err


def test_allocate_monitors_contract_keys():
    result = _json(allocate_monitors.Command(), STATS)
    assert {"feasible", "objective", "allocation", "cpu"} <= set(result)
    assert result["feasible"] is True and result["status"] == "optimal"
    assert len(result["allocation"]) == 50
    assert result["cpu"]["edge"] <= 20.0 + 1e-9
    assert result["objective"] == pytest.approx(10.0 * len(result["received"]["desktop"]))


def test_allocate_monitors_filters_several_periods(tmp_path):
    doc = json.loads(Path(STATS).read_text())
    doc["nodes"][0]["available_cpu"] = 100.0
    calm = tmp_path / "calm.json"
    calm.write_text(json.dumps(doc))
    # nine calm periods and the busy one: the SMA of edge availability is 92 %, nothing has to move
    result = _json(allocate_monitors.Command(), *[str(calm)] * 9, STATS)
    assert result["migrations"] == [] and result["capacity"]["edge"] == pytest.approx(92.0)
    # with a window of 1 only the busy period counts
    result = _json(allocate_monitors.Command(), *[str(calm)] * 9, STATS, "--window", "1")
    assert len(result["migrations"]) >= 24


def test_allocate_monitors_human_summary():
    out = StringIO()
    call_command(allocate_monitors.Command(), STATS, stdout=out)
    assert out.getvalue().startswith("feasible (optimal): total delay")


def test_allocate_monitors_bad_input(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"format": "continuum.monitorstats/v1", "nodes": [{"name": "a"}], "monitors": []}))
    code, captured = _exit(allocate_monitors.Command(), "allocate_monitors", str(bad), capsys=capsys)
    assert code == 2 and "bad.json: node 'a': available_cpu: expected a number" in captured.err
    broken = tmp_path / "broken.json"
    broken.write_text("{")
    code, captured = _exit(allocate_monitors.Command(), "allocate_monitors", str(broken), capsys=capsys)
    assert code == 2 and "malformed JSON" in captured.err
