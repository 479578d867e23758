"""benchmarks/thesis.py, the chapter-4 harness (CONTRACTS.md, third round): its rows' contract, the labels of the
thesis-scenario rows, the hardware-only rows and argument validation. Only the quick rows are run here."""

import json

from benchmarks import thesis

CONTRACT = {"id", "thesis", "ours", "origin", "how"}
HOWS = {"model", "real processes", "live cluster", "real nodes", "not measurable"}


def test_rows_follow_the_contract_and_label_the_thesis_scenarios(tmp_path, capsys):
    out = tmp_path / "out.json"
    assert thesis.main(["--only", "T4.16,T4.27,F4.14,F4.4,T4.29,T4.5", "--json", str(out)]) == 0
    rows = {r["id"]: r for r in json.loads(out.read_text())["rows"]}
    assert set(rows) == {"T4.16", "T4.27", "F4.14", "F4.4", "T4.29", "T4.5"}
    for r in rows.values():
        assert set(r) >= CONTRACT and r["how"] in HOWS
        assert r["origin"] in ("untuned", "thesis scenario") or r["how"] == "not measurable"
    # fixtures built from the thesis' results are never presented as reproductions
    assert rows["T4.16"]["origin"] == "thesis scenario" and rows["T4.27"]["origin"] == "thesis scenario"
    assert rows["F4.14"]["origin"] == "untuned" and rows["F4.14"]["ours"]["default_never_above_kl"] is True
    for hw in ("F4.4", "T4.5", "T4.29"):  # Jetson UMA boards; root for SCHED_DEADLINE
        assert rows[hw]["ours"] is None and rows[hw]["reason"]
    printed = capsys.readouterr().out
    assert "thesis scenario" in printed and "not measurable" in printed


def test_every_chapter_4_table_and_figure_has_a_row():
    ids = {*thesis.COMPUTED, *(r["id"] for r in thesis.STATIC)}
    assert {f"T4.{i}" for i in range(1, 37)} <= ids
    assert {f"F4.{i}" for i in range(1, 25)} <= ids


def test_unknown_id_exits_2_with_one_line(capsys):
    assert thesis.main(["--only", "T4.99"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "unknown id 'T4.99'" in err[0]
