"""Shared fixtures of the Python package's tests: the repository's root, the command-line
tool built by cargo, and the Panda's Pinocchio fixture."""

import json
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def cli():
    """The `mechanism` binary: MECHANISM_CLI, else cargo's debug or release build in the
    repository's target folder (CARGO_TARGET_DIR when set). `cargo test --workspace` (run
    first by .ci/run) or `cargo build` builds it."""
    given = os.environ.get("MECHANISM_CLI")
    if given:
        return given
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    for profile in ("debug", "release"):
        path = target / profile / "mechanism"
        if path.is_file():
            return str(path)
    pytest.fail("no `mechanism` binary: run `cargo build` first (or set MECHANISM_CLI)")


@pytest.fixture(scope="session")
def panda_fixture():
    with open(ROOT / "tests" / "fixtures" / "panda_pinocchio.json") as f:
        return json.load(f)
