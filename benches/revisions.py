"""The timing harness built at other commits, for the before/after tables.

A commit's sources are unpacked with `git archive` into target/bench-revs/<commit>/src (no
worktree, nothing in .git changes); the current tree's benches/harness is copied beside them
as a crate of its own whose `mechanism` dependency is that commit's crate, and built in one
target directory shared by all revisions (dependencies compiled once). A commit older than
`Mechanism::evaluate_into` or `StepController` gets the harness's `legacy-evaluate` or
`legacy-controller` feature (the buffer written from `evaluate`'s return value, as a caller
of that version would; the PI controller only).
"""

import os
import shutil
import subprocess

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
REVS = os.path.join(ROOT, "target", "bench-revs")

MANIFEST = """[package]
name = "mechanism-harness"
version = "0.1.0"
edition = "2024"
publish = false

[workspace]

[features]
legacy-evaluate = []
legacy-controller = []

[dependencies]
mechanism = { package = "{package}", path = "../..", features = ["builtin"] }

[[bin]]
name = "harness"
path = "src/main.rs"
"""


def sha(rev):
    """The full commit id of `rev`."""
    return subprocess.run(["git", "rev-parse", rev], cwd=ROOT, check=True, capture_output=True,
                          text=True).stdout.strip()


def head_is(rev):
    """Whether `rev` is the checked-out commit and the tree has no changes under src/,
    codegen/, mechanism-macros/, math/ (then the workspace build is that revision)."""
    if sha(rev) != sha("HEAD"):
        return False
    dirty = subprocess.run(["git", "status", "--porcelain", "--", "src", "codegen", "mechanism-macros",
                            "math", "mechanisms", "benches/harness", "benches/mechanisms"],
                           cwd=ROOT, check=True, capture_output=True, text=True).stdout.strip()
    return not dirty


def build(rev, native=False, log=print):
    """Builds the harness at `rev` (portable, or with -C target-cpu=native); returns the
    executable's path."""
    full = sha(rev)
    src = os.path.join(REVS, full[:12], "src")
    if not os.path.exists(os.path.join(src, "Cargo.toml")):
        os.makedirs(src, exist_ok=True)
        archive = subprocess.run(["git", "archive", full], cwd=ROOT, check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", src], input=archive, check=True)
    crate = os.path.join(src, "benches", "harness-current")
    if os.path.exists(crate):
        shutil.rmtree(crate)
    shutil.copytree(os.path.join(ROOT, "benches", "harness", "src"), os.path.join(crate, "src"))
    # The harness reads its mechanisms from `mechanisms/` beside its manifest (a link to
    # benches/mechanisms, so that its package holds them).
    os.symlink(os.path.join("..", "mechanisms"), os.path.join(crate, "mechanisms"))
    # The root package was `mechanism` before it became `mechanism-dynamics` (the library's
    # import name is `mechanism` either way).
    with open(os.path.join(src, "Cargo.toml")) as f:
        package = "mechanism-dynamics" if 'name = "mechanism-dynamics"' in f.read() else "mechanism"
    with open(os.path.join(crate, "Cargo.toml"), "w") as f:
        f.write(MANIFEST.replace("{package}", package))
    shutil.copy(os.path.join(src, "Cargo.lock"), os.path.join(crate, "Cargo.lock"))
    features = []
    with open(os.path.join(src, "src", "system", "mechanism.rs")) as f:
        if "fn evaluate_into" not in f.read():
            features.append("legacy-evaluate")
    with open(os.path.join(src, "src", "integrators", "mod.rs")) as f:
        if "enum StepController" not in f.read():
            features.append("legacy-controller")
    target = os.path.join(REVS, "target-native" if native else "target")
    env = dict(os.environ, CARGO_TARGET_DIR=target)
    if native:
        env["RUSTFLAGS"] = (env.get("RUSTFLAGS", "") + " -C target-cpu=native").strip()
    cmd = ["cargo", "build", "--release", "--offline", "--manifest-path", os.path.join(crate, "Cargo.toml")]
    if features:
        cmd += ["--features", ",".join(features)]
    log(f"building the harness at {full[:12]}{' (native)' if native else ''} {' '.join(features)}")
    subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL)
    # One binary name for every revision in the shared target directory: keep a copy.
    exe = os.path.join(REVS, full[:12], "harness-native" if native else "harness")
    shutil.copy(os.path.join(target, "release", "harness"), exe)
    return exe
