"""The seed paper's crank-slider through Python equals the command-line tool's run of the
same declaration: both take the interpreter route, the same assembly and the same DOP853
steps, so every sample agrees bit for bit (the CSV prints each value's shortest exact
decimal), and so do the summary's figures."""

import csv
import json
import subprocess

import numpy as np

import mechanism


def cli_run(cli, root, tmp_path, *args):
    out = tmp_path / "out"
    subprocess.run(
        [cli, "simulate", str(root / "mechanisms" / "spatial_crank_slider.mech"),
         "--out", str(out), "--figures", "none", "--no-animation", *args],
        check=True, capture_output=True, text=True,
    )
    with open(out / "trajectory.csv") as f:
        rows = list(csv.reader(f))
    header, values = rows[0], np.array(rows[1:], dtype=float)
    with open(out / "summary.json") as f:
        summary = json.load(f)
    return header, values, summary


def test_the_seed_through_python_equals_the_cli_run(cli, root, tmp_path):
    header, table, summary = cli_run(cli, root, tmp_path)
    seed = mechanism.load(str(root / "mechanisms" / "spatial_crank_slider.mech"))
    run = seed.simulate()  # the command's defaults: 10 s, DOP853 at 1e-10, 100 samples/s
    n = len(seed.coordinates)
    assert header[: 1 + 3 * n] == ["t"] + seed.coordinates + [
        f"{c}_dot" for c in seed.coordinates] + [f"{c}_ddot" for c in seed.coordinates]
    assert table.shape[0] == len(run.t) == 1001
    np.testing.assert_array_equal(table[:, 0], run.t)
    np.testing.assert_array_equal(table[:, 1 : 1 + n], run.q)
    np.testing.assert_array_equal(table[:, 1 + n : 1 + 2 * n], run.qd)
    np.testing.assert_array_equal(table[:, 1 + 2 * n : 1 + 3 * n], run.qdd)
    assert summary["steps"] == run.steps
    assert summary["rejected_steps"] == run.rejected_steps
    assert summary["rhs_evaluations"] == run.rhs_evaluations
    assert summary["max_constraint_error"] == run.max_constraint_error
    assert summary["max_energy_balance_error"] == run.max_energy_balance_error


def test_options_and_parameters_reach_the_run_as_on_the_command_line(cli, root, tmp_path):
    _, table, summary = cli_run(
        cli, root, tmp_path, "--t-end", "2", "--integrator", "dopri5", "--rtol", "1e-8",
        "--atol", "1e-9", "--set", "l2=0.35", "--init", "der(phi)=3",
        "--samples-per-second", "50",
    )
    seed = mechanism.load(str(root / "mechanisms" / "spatial_crank_slider.mech"))
    run = seed.simulate(t_end=2.0, integrator="dopri5", rtol=1e-8, atol=1e-9,
                        set={"l2": 0.35}, init={"der(phi)": 3.0}, samples_per_second=50.0)
    np.testing.assert_array_equal(table[:, 1:5], run.q)
    assert run.qd0[0] == 3.0
    assert summary["steps"] == run.steps
