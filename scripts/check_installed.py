"""Check contactres as a user who installs it gets it: the built wheel, no extras, no repository.

Issue 30: "installed = cloned". This script (run by ``.ci/run`` after the test suite):

1. builds the wheel of this checkout (``pip wheel --no-deps``, in an isolated build
   environment: the setuptools the project asks for);
2. makes a fresh virtual environment in a temporary folder and installs the wheel there with
   its dependencies only (no extras: no xarray, dask, igor2, h5py);
3. from an empty folder outside the repository runs ``contactres --help``, ``contactres
   examples --copy .``, the ``Example:`` command of every subcommand's ``--help`` verbatim
   (the demo included: a step that needs an extra must say so in one line and be left out; a
   command that needs one altogether must say which, in one line),
   and the README's first Python lines (those that run on the bundled data).

Every command must exit 0 and print no traceback; the script prints one line per command with
its time and exits 1 at the first failure, with the command's output. Usage::

    python scripts/check_installed.py [--keep DIR]
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# Lists every subcommand's Example: line, run inside the installed environment (its click
# application, not the repository's source).
_LIST_EXAMPLES = r"""
import json, re
import click
from contactres.cli import main

def walk(group, words):
    ctx = click.Context(group, info_name="contactres")
    for name in group.list_commands(ctx):
        cmd = group.get_command(ctx, name)
        path = [*words, name]
        if isinstance(cmd, click.Group):
            yield from walk(cmd, path)
        else:
            yield path

out = []
for words in walk(main, []):
    out.append(words)
print(json.dumps(out))
"""

_EXAMPLE = re.compile(r"^\s*Example: (contactres .*?)(?:\n\s*\n|\Z)", re.M | re.S)


# The one line of a command that needs an optional extra (contactres.errors.MissingExtraError).
_NEEDS_EXTRA = re.compile(r"^contactres: error: .* pip install 'contactres\[[a-z,]+\]'$")


def _run(
    args, cwd: Path, env: dict, timeout: int = 600, extra_ok: bool = False
) -> subprocess.CompletedProcess:
    """Run ``args``; fail on a non-zero exit or a traceback, except (``extra_ok``) the one line
    of a command that needs an optional extra this environment does not have."""
    start = time.perf_counter()
    done = subprocess.run(
        args, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout, check=False
    )
    shown = " ".join(args) if isinstance(args, list) else args
    print(f"{time.perf_counter() - start:6.1f} s  {shown[:110]}", flush=True)
    said = done.stderr.strip().splitlines()
    if extra_ok and done.returncode != 0 and len(said) == 1 and _NEEDS_EXTRA.match(said[0]):
        print(f"         needs an extra, said in one line: {said[0]}", flush=True)
        return done
    if done.returncode != 0 or "Traceback" in done.stdout + done.stderr:
        print(done.stdout[-3000:], done.stderr[-3000:], sep="\n", file=sys.stderr)
        raise SystemExit(f"check_installed: FAILED: {shown}")
    return done


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--keep", type=Path, help="work in this folder and keep it")
    args = parser.parse_args()
    base = args.keep or Path(tempfile.mkdtemp(prefix="contactres-installed-"))
    base.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONDONTWRITEBYTECODE="1")
    env.pop("PYTHONPATH", None)  # nothing of the repository on the path

    wheels = base / "wheel"
    _run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q",
         "-w", str(wheels), str(ROOT)],
        base, env,
    )  # fmt: skip
    wheel = next(wheels.glob("contactres-*.whl"))
    prefix = base / "venv"
    venv.EnvBuilder(with_pip=True, clear=True).create(prefix)
    python, bin_dir = prefix / "bin" / "python", prefix / "bin"
    _run([str(python), "-m", "pip", "install", "-q", str(wheel)], base, env)
    env["PATH"] = f"{bin_dir}{os.pathsep}{env.get('PATH', '')}"
    work = base / "work"
    work.mkdir(exist_ok=True)

    _run(["contactres", "--help"], work, env)
    _run(["contactres", "examples", "--copy", "."], work, env)
    commands = json.loads(_run([str(python), "-c", _LIST_EXAMPLES], work, env).stdout)
    for words in commands:
        text = _run(["contactres", *words, "--help"], work, env).stdout
        match = _EXAMPLE.search(text)
        if match is None:
            raise SystemExit(
                f"check_installed: 'contactres {' '.join(words)} --help' has no Example"
            )
        # As a user pastes it: lines joined by the shell's " \" continuation.
        line = shlex.split(match.group(1).replace("\\\n", " "))
        if words == ["qcm", "analyze"]:
            line += ["--bootstrap", "0"]  # the example's analysis, faster; the same files
        _run(line, work, env, extra_ok=True)
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    first = re.search(r"```python\n(.*?)```", readme, re.S)
    if first is not None:
        (work / "readme_first.py").write_text(first.group(1), encoding="utf-8")
        _run([str(python), "readme_first.py"], work, env)
    # The README's shell lines that start from the examples (the block with 'contactres examples
    # --copy'), up to the 'cd ..' that ends the bundled-data part (the lines after it name a
    # user's own sweeps.csv), through the shell, in a folder of their own.
    blocks = re.findall(r"```sh\n(.*?)```", readme, re.S)
    shell = next((b for b in blocks if "contactres examples --copy" in b), None)
    if shell is not None:
        lines = []
        for line in shell.splitlines():
            lines.append(line.split("#", 1)[0].strip())
            if line.strip().startswith("cd .."):
                break
        readme_dir = work / "readme"
        readme_dir.mkdir(exist_ok=True)
        _run(["bash", "-euc", " && ".join(x for x in lines if x)], readme_dir, env)
    print(f"check_installed: OK ({len(commands)} commands) in {base}")


if __name__ == "__main__":
    main()
