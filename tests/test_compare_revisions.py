"""benchmarks/compare_revisions.py: parsing of benchmark outputs, the before/after table, the child tree's CPU time
and argument validation. No benchmark is run here."""

import sys
import textwrap
from pathlib import Path

import pytest

from benchmarks import compare_revisions as cr

REMAP = """\
DAG: 1000 tasks, 1204 edges; cluster: 50 nodes x 2 CPUs, full mesh
HEFT4K from scratch: look-ahead 2104 ms (makespan 18.5), plain HEFT 839 ms
  lose  n21:  17 tasks lost ( 1.7% of the rank) -> partial in  100.0 ms; makespan 18.5 -> 19.2 (partial 19.2 in 1.0 ms)
  lose  n26:  20 tasks lost ( 2.0% of the rank) -> partial in   50.0 ms; makespan 18.5 -> 19.7 (partial 19.7 in 2.0 ms)
"""

ROS = """\
  N method                     containers  largest   B/s between   share       ms  note
 24 one node per container             24        1     1,385,813  100.0%     0.01
  2 Listing 3.20                        2       15       211,627   15.3%     0.55
  2 greedy modularity                   2       12       143,360   10.3%    11.06
  3 Listing 3.20                        3        9       252,587   18.2%     5.10
super-clustering   inter-node   1.40 Mbps  (7.84 ms)
"""

KAIROS = """\
=== synthetic-4.5.1: 50 monitors on edge, desktop, server (thresholds {}), simulated in 0.8 s ===
  milp_mean_ms                     46.656
=== rb-kairos-4.5.2: 201 monitors on mcb, jetson, server (thresholds {}), simulated in 49.8 s ===
  milp_mean_ms                     1618.426
"""


def test_headlines_parse_the_figures_each_benchmark_prints():
    assert cr.HEADLINES["remap_speed"](REMAP) == {"mean partial remap ms": 75.0, "heft4k scratch ms": 2104.0}
    ros = cr.HEADLINES["ros_clustering"](ROS)
    assert ros["Listing 3.20 total ms"] == pytest.approx(5.65)
    assert ros["super-clustering Table 4.26 ms"] == 7.84
    assert cr.HEADLINES["kairos_monitors"](KAIROS) == {
        "synthetic simulated s": 0.8,
        "synthetic MILP mean ms": 46.656,
        "rb simulated s": 49.8,
        "rb MILP mean ms": 1618.426,
    }


def test_headline_is_none_when_the_output_changed_shape():
    assert cr.HEADLINES["remap_speed"]("something else") == {"mean partial remap ms": None, "heft4k scratch ms": None}


def run(cpu: float, code: int = 0, headline: dict | None = None) -> cr.Run:
    return cr.Run(code, cpu, cpu * 2, 100.0, 1.0, 2.0, "", headline or {})


def test_table_gives_the_ratio_marks_new_and_failed_runs():
    results = {
        "remap_speed": (run(10.0, headline={"x ms": 4.0}), run(12.0, headline={"x ms": 2.0})),
        "heft_scale": (None, run(3.0)),
        "orb_frames": (run(1.0), run(1.0, code=1)),
    }
    text = cr.render(results, {"remap_speed": ["--failures", "5"], "heft_scale": [], "orb_frames": []})
    lines = {line.split()[0]: line for line in text.splitlines()[1:] if line.strip()}
    assert lines["remap_speed"].split()[1:4] == ["10", "12", "1.20"]
    assert lines["remap_speed:"] == "remap_speed: --failures 5"
    assert lines["orb_frames:"] == "orb_frames: (no arguments)"
    assert lines["x"].split()[2:5] == ["4", "2", "0.50"]
    assert lines["heft_scale"].split()[1:4] == ["new", "3", "new"]
    assert "FAILED (after exit 1)" in lines["orb_frames"]


def test_heft_scale_rows_are_read_whatever_their_width():
    text = "tasks  procs  edges  heft() s\n 5000     64  16000    0.3049  1\n12500     64  40021    0.8703  2\n"
    assert cr.HEADLINES["heft_scale"](text) == {"heft() CPU s, 5000 tasks": 0.3049, "heft() CPU s, 12500 tasks": 0.8703}


def test_cpu_time_counts_the_whole_child_tree(tmp_path: Path):
    """A benchmark whose work runs in a grandchild (saga, rtamt peers) is charged for it."""
    (tmp_path / "benchmarks").mkdir()
    spin = "import time\nt = time.process_time()\nwhile time.process_time() - t < 0.3:\n    pass\n"
    (tmp_path / "benchmarks" / "spin.py").write_text(
        textwrap.dedent(
            f"""\
            import subprocess, sys
            subprocess.run([sys.executable, "-c", {spin!r}], check=True)
            print("done 1.5 ms")
            """
        )
    )
    got = cr.run_benchmark(Path(sys.executable), tmp_path, "spin", [], {"PATH": "/usr/bin:/bin"}, timeout=120)
    assert got.returncode == 0
    assert got.output.strip() == "done 1.5 ms"
    assert got.cpu_s >= 0.3


def test_unknown_benchmark_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as exc:
        cr.parse_args(["--benchmarks", "nope"])
    assert exc.value.code == 2
    assert "unknown benchmark(s) nope" in capsys.readouterr().err
