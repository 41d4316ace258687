"""Where the benchmark programs put what they build and measure: cargo's target directory
(`CARGO_TARGET_DIR` when set, else `target/` of the checkout), its `bench-results/` (every
step's results, run.json) and its `criterion/` (criterion's estimates)."""

import os

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
TARGET = os.path.abspath(os.environ.get("CARGO_TARGET_DIR") or os.path.join(ROOT, "target"))
RESULTS = os.path.join(TARGET, "bench-results")
CRITERION = os.path.join(TARGET, "criterion")
