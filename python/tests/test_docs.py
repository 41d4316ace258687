"""The Python examples of the README and of the book's Python chapter run as written (from
the repository's root, where their relative paths point), as the Rust examples run as
doc-tests."""

import os
import re

import pytest

DOCUMENTS = ["README.md", "docs/src/python.md"]


def blocks(root):
    for doc in DOCUMENTS:
        text = (root / doc).read_text()
        for k, m in enumerate(re.finditer(r"```python\n(.*?)```", text, re.S)):
            yield pytest.param(m.group(1), id=f"{doc}#{k}")


def pytest_generate_tests(metafunc):
    if "code" in metafunc.fixturenames:
        from conftest import ROOT

        metafunc.parametrize("code", list(blocks(ROOT)))


def test_the_example_runs(code, root, monkeypatch):
    if "import ray" in code:
        try:
            import ray  # noqa: F401
        except ImportError:
            if os.environ.get("MECHANISM_REQUIRE_RAY"):
                raise
            pytest.skip("ray is not installed")
    monkeypatch.chdir(root)
    exec(compile(code, "<example>", "exec"), {"__name__": "__example__"})
