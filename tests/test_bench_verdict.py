"""Tests of the verdict of ``make bench`` (benchmarks/_verdict.py and benchmarks/run_all.py):
every line a benchmark prints with ``TARGET`` is read back and judged, in seconds, MB or a
ratio, and a ``TARGET`` line in another layout fails the run instead of passing unread."""

import importlib
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"


@pytest.fixture
def bench(monkeypatch):
    monkeypatch.syspath_prepend(str(BENCHMARKS))
    verdict = importlib.import_module("_verdict")
    run_all = importlib.import_module("run_all")
    yield verdict, run_all
    for name in ("_verdict", "run_all"):
        sys.modules.pop(name, None)


def test_target_lines_read_back_in_every_unit(bench, capsys):
    verdict, _ = bench
    assert verdict.target("curve (CPU)", 0.012, 0.015) is True
    assert verdict.target("peak memory", 612.0, 500.0, unit="MB") is False
    assert verdict.target("shipped / one thread", 1.1, 1.2, unit="x") is True
    lines = capsys.readouterr().out.splitlines()
    read = [verdict.parse_target(line) for line in lines]
    assert [(t.name, t.value, t.target, t.met, t.unit) for t in read] == [
        ("curve (CPU)", 0.012, 0.015, True, "s"),
        ("peak memory", 612.0, 500.0, False, "MB"),
        ("shipped / one thread", 1.1, 1.2, True, "x"),
    ]
    # the older four-field reading still works (the other benchmarks' callers)
    assert verdict.parse(lines[0]) == ("curve (CPU)", 0.012, 0.015, True)
    assert verdict.parse("  a line with no target") is None


def test_best_time_counts_cpu_not_waiting(bench):
    verdict, _ = bench
    import time

    assert verdict.best_time(lambda: time.sleep(0.05), repeat=1) < 0.02
    assert verdict.best_time(lambda: time.sleep(0.05), repeat=1, clock="wall") >= 0.05
    with pytest.raises(ValueError, match="clock"):
        verdict.best_time(lambda: None, clock="gpu")


def test_verdict_reports_missed_and_unread_targets(bench):
    verdict, run_all = bench
    T = verdict.Target
    outcomes = {
        "bench_a.py": ([T("curve", 0.01, 0.015, True, "s")], 0),
        "bench_b.py": ([T("peak memory", 612.0, 500.0, False, "MB")], 1),
        "bench_c.py": (
            [T("TARGET x: 3 GB (no layout)", float("nan"), float("nan"), False, "unread")],
            1,
        ),
    }
    line = run_all.verdict(outcomes)
    assert line.startswith("bench: 2 of 3 targets MISSED")
    assert "bench_b.py: peak memory 6.1e+02 MB vs 500 MB" in line
    assert "bench_c.py: unread target line" in line


def test_run_reads_every_target_line_of_a_benchmark(bench, tmp_path, capsys):
    _, run_all = bench
    script = tmp_path / "bench_fake.py"
    script.write_text(
        "print('  TARGET memory: 120 MB, target 500 MB, ratio 0.24 -> met')\n"
        "print('  TARGET by hand: 3 GB of 2 GB -> MISSED')\n"
        "print('no target here')\n"
    )
    targets, code = run_all.run(script)
    capsys.readouterr()
    assert code == 0
    assert [(t.name, t.unit, t.met) for t in targets] == [
        ("memory", "MB", True),
        ("TARGET by hand: 3 GB of 2 GB -> MISSED", "unread", False),
    ]


def _marking(one: list):
    """A stand-in for ``one_thread``: the calls it wraps set ``one[0]`` to "one" while they run
    (``one[0]`` is "shipped" otherwise), so a call can tell which side ran it."""

    def one_thread(f):
        def call():
            one[0] = "one"
            try:
                return f()
            finally:
                one[0] = "shipped"

        return call

    return one_thread


def test_shipped_and_one_thread_warms_up_then_times_abba(bench, monkeypatch):
    # the first call (lazy imports, new BLAS threads spinning) is not timed, and neither side
    # is always timed after the other (a drift over the first calls would favour it)
    verdict, _ = bench
    calls = []

    def fn():
        calls.append(one[0])

    one = ["shipped"]
    # CPU time of a run = its position in the sequence: the best of each side shows where
    # each side's runs fell
    monkeypatch.setattr(verdict, "one_thread", _marking(one))
    monkeypatch.setattr(verdict, "timed", lambda f: (f(), float(len(calls)), 0.0))
    shipped, single = verdict.shipped_and_one_thread(fn, repeat=3)
    assert calls == ["shipped", "shipped", "one", "one", "shipped", "shipped", "one"]
    assert (shipped, single) == (2.0, 3.0)


def test_shipped_and_one_thread_of_builds_each_run_anew(bench, monkeypatch):
    # a call built for each run (a material never seen: bench_dcsf), run 0 untimed, the timed
    # runs in the order ABBA, every run its own call
    verdict, _ = bench
    calls = []
    one = ["shipped"]

    def make(i):
        return lambda: calls.append((i, one[0]))

    monkeypatch.setattr(verdict, "one_thread", _marking(one))
    monkeypatch.setattr(verdict, "timed", lambda f: (f(), float(len(calls)), 0.0))
    shipped, single = verdict.shipped_and_one_thread_of(make, repeat=2)
    assert calls == [(0, "shipped"), (1, "shipped"), (2, "one"), (4, "one"), (3, "shipped")]
    assert (shipped, single) == (2.0, 3.0)
