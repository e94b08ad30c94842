"""The documentation site's sources agree with the package (the build itself is ``make docs``).

* The API reference lists every public name of ``contactres`` under its defining module, so a
  name added to ``contactres.__all__`` cannot be missing from the reference.
* The README links the docs' entry page, and that page exists.
"""

import re
from pathlib import Path

import contactres

DOCS = Path(__file__).resolve().parents[2] / "docs"
README = DOCS.parent / "README.md"


def test_the_api_reference_lists_every_public_name_at_its_module():
    listed = set(re.findall(r"^   ~([\w.]+)$", (DOCS / "api.md").read_text(encoding="utf-8"), re.M))
    names = [n for n in contactres.__all__ if n != "__version__"]  # a string, not an object
    expected = {f"{getattr(contactres, n).__module__}.{n}" for n in names}
    assert sorted(expected - listed) == []
    assert sorted(listed - expected) == []


def test_the_readme_links_the_docs_entry_page():
    assert "](docs/index.md)" in README.read_text(encoding="utf-8")
    assert (DOCS / "index.md").is_file()
