"""Rewrite the data-dictionary blocks of README.md from the package's schema (run after a change).

.venv/bin/python scripts/update_readme.py
"""

from __future__ import annotations

from pathlib import Path

from contactres.report.dictionary import update_blocks

README = Path(__file__).resolve().parents[1] / "README.md"


def main() -> None:
    text = README.read_text(encoding="utf-8")
    new = update_blocks(text)
    if new != text:
        README.write_text(new, encoding="utf-8")
        print(f"updated {README}")
    else:
        print(f"{README} is up to date")


if __name__ == "__main__":
    main()
