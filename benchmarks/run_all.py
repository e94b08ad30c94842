"""Run every ``benchmarks/bench_*.py`` and end with a one-line verdict (``make bench``).

Each benchmark runs in its own interpreter (this one's), its output shown as it comes; a failing
benchmark does not stop the others. The targets are read back from the ``TARGET`` lines that
:func:`_verdict.target` prints, whatever their unit (seconds of CPU time, MB, a ratio); a line
that mentions ``TARGET`` but cannot be read is reported as an unread target and fails the run
(a target printed by hand in another layout would otherwise go unjudged). Exit status 1 if any
target was missed or unread, or any benchmark failed (non-zero exit without a missed target,
e.g. an exception), else 0.

Run: ``.venv/bin/python benchmarks/run_all.py [bench_x.py ...]`` (default: all of them).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from _verdict import Target, parse_target

HERE = Path(__file__).resolve().parent


def run(path: Path) -> tuple[list[Target], int]:
    """Run one benchmark, echoing its output; return its targets and exit status (a line that
    mentions ``TARGET`` but is not one :func:`_verdict.target` prints is a missed target with
    unit "unread")."""
    print(f"== {path.name}", flush=True)
    env = dict(os.environ, PYTHONUNBUFFERED="1")  # show progress as it comes
    proc = subprocess.Popen(
        [sys.executable, str(path)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=env,
    )
    targets = []
    assert proc.stdout is not None
    for line in proc.stdout:
        print(line, end="", flush=True)
        parsed = parse_target(line)
        if parsed is not None:
            targets.append(parsed)
        elif "TARGET " in line:
            targets.append(Target(line.strip(), float("nan"), float("nan"), False, "unread"))
    return targets, proc.wait()


def verdict(outcomes: dict[str, tuple[list[Target], int]]) -> str:
    """The one-line summary of all benchmarks' targets and failures."""
    n_targets = sum(len(t) for t, _ in outcomes.values())
    missed = [
        f"{bench}: unread target line {t.name!r}"
        if t.unit == "unread"
        else f"{bench}: {t.name} {t.value:.2g} {t.unit} vs {t.target:g} {t.unit}"
        for bench, (targets, _) in outcomes.items()
        for t in targets
        if not t.met
    ]
    # A non-zero exit with no missed target is a failure of the benchmark itself.
    failed = [
        f"{bench} failed (exit {code})"
        for bench, (targets, code) in outcomes.items()
        if code != 0 and all(t.met for t in targets)
    ]
    silent = [bench for bench, (targets, code) in outcomes.items() if not targets and code == 0]
    n_bench = len(outcomes)
    head = f"bench: {n_bench} benchmark{'s' * (n_bench != 1)}, {n_targets} targets"
    if missed:
        head = f"bench: {len(missed)} of {n_targets} targets MISSED ({'; '.join(missed)})"
    elif not failed:
        head += ", all met"
    notes = failed + ([f"no targets reported by {', '.join(silent)}"] if silent else [])
    return head + "".join(f"; {n}" for n in notes)


def main(argv: list[str] | None = None) -> int:
    names = sys.argv[1:] if argv is None else argv
    paths = [HERE / n for n in names] if names else sorted(HERE.glob("bench_*.py"))
    outcomes = {p.name: run(p) for p in paths}
    line = verdict(outcomes)
    print(line)
    ok = all(code == 0 and all(x.met for x in t) for t, code in outcomes.values())
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
