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
   and then the README: every shell command and Python block in document order (the
   Python blocks in one namespace), as a user pastes them (all but `make demo`/`make test`,
   which need the repository, and a command that needs the user's own dask cluster).

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
import shutil
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


# Runs the README's blocks in the installed environment (python run_readme.py README.md):
# ```python blocks are executed in one namespace; ```sh / ```bash blocks command by command
# (a trailing " \" joins lines; `cd DIR` moves the folder of the commands that follow; a block
# that says "in a folder holding the examples" runs in examples/, where the first shell block
# copied them). A command may fail only with the one line of a missing optional extra; a
# command that needs a dask cluster of the user's (--scheduler tcp://...) is not run.
_README_RUNNER = r"""
import os, re, subprocess, sys
from pathlib import Path

NEEDS_EXTRA = re.compile(r"^contactres: error: .* pip install 'contactres\[[a-z,]+\]'$")
text = Path(sys.argv[1]).read_text(encoding="utf-8")
home = Path.cwd()
namespace = {"__name__": "__readme__"}
for lang, code in re.findall(r"^```(\w*)\n(.*?)^```", text, re.S | re.M)[1:]:
    if lang == "python":
        print("python block:", code.splitlines()[0][:90], flush=True)
        try:
            exec(compile(code, "<README block>", "exec"), namespace)
        except Exception as exc:
            from contactres.errors import MissingExtraError
            if not isinstance(exc, MissingExtraError):
                raise
            print("  needs an extra, said so:", exc, flush=True)
        continue
    if lang not in ("sh", "bash"):
        continue
    cwd = home / "examples" if "in a folder holding the examples" in code else home
    missing = None
    for command in code.replace("\\\n", " ").splitlines():
        command = command.split("#", 1)[0].strip()
        if not command or "--scheduler tcp://" in command:
            continue
        if missing is not None:  # the block's later commands build on what that one makes
            print(f"  left out (the block needs {missing}): {command[:80]}", flush=True)
            continue
        for part in command.split("&&"):
            part = part.strip()
            if part.startswith("cd "):
                cwd = (cwd / part[3:].strip()).resolve()
                continue
            print(f"  {part[:100]}", flush=True)
            done = subprocess.run(part, shell=True, cwd=cwd, capture_output=True, text=True)
            said = done.stderr.strip().splitlines()
            if done.returncode != 0 and len(said) == 1 and NEEDS_EXTRA.match(said[0]):
                print("  needs an extra, said in one line:", said[0], flush=True)
                missing = said[0].rsplit("pip install ", 1)[-1]
                break
            if done.returncode != 0 or "Traceback" in done.stdout + done.stderr:
                print(done.stdout[-3000:], done.stderr[-3000:], sep="\n", file=sys.stderr)
                raise SystemExit(f"README command failed: {part}")
print("README: every block ran", flush=True)
"""


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
    # The README, every block in document order, as a user pastes them (its first block, `make
    # demo` / `make test`, needs the repository; the layout tree is no code): Python blocks in
    # one namespace, shell commands one by one, in a folder of their own (_README_RUNNER).
    readme_dir = work / "readme"
    readme_dir.mkdir(exist_ok=True)
    (readme_dir / "run_readme.py").write_text(_README_RUNNER, encoding="utf-8")
    shutil.copyfile(ROOT / "README.md", readme_dir / "README.md")
    _run([str(python), "run_readme.py", "README.md"], readme_dir, env, timeout=1800)
    print(f"check_installed: OK ({len(commands)} commands) in {base}")


if __name__ == "__main__":
    main()
