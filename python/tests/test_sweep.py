"""Sweeps: `mechanism.sweep` runs many simulations on all cores and equals the same runs
done one by one; a model pickles to its text and parameter values, so a Ray task can take
one, and a Ray sweep (local, 2 CPUs) equals the same runs done one by one too."""

import os
import pickle

import numpy as np
import pytest

import mechanism

SETS = [{"l2": 0.3 + 0.01 * k, "tau0": 0.005 * (1 + k % 3)} for k in range(6)]
OPTIONS = dict(t_end=1.0, rtol=1e-9, atol=1e-9, samples_per_second=20.0)


def same(a, b):
    for field in ("t", "q", "qd", "qdd", "multipliers", "work"):
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field), err_msg=field)
    assert (a.steps, a.rhs_evaluations) == (b.steps, b.rhs_evaluations)


@pytest.fixture(scope="module")
def seed():
    return mechanism.load("spatial_crank_slider")


@pytest.fixture(scope="module")
def one_by_one(seed):
    return [seed.simulate(set=s, **OPTIONS) for s in SETS]


def test_sweep_equals_the_runs_one_by_one(seed, one_by_one):
    runs = mechanism.sweep(seed, SETS, **OPTIONS)
    assert len(runs) == len(SETS)
    for run, single, s in zip(runs, one_by_one, SETS):
        assert run.parameters["l2"] == s["l2"]
        same(run, single)
    # A longer rod changes the motion: the sets did reach the runs.
    assert np.abs(runs[0].q - runs[-1].q).max() > 1e-3


def test_a_model_pickles_to_its_text_and_values(seed, one_by_one):
    changed = mechanism.load("spatial_crank_slider", set={"l2": 0.32})
    for model in (seed, changed):
        copy = pickle.loads(pickle.dumps(model))
        assert copy.source == model.source and copy.parameters == model.parameters
    same(pickle.loads(pickle.dumps(seed)).simulate(set=SETS[2], **OPTIONS), one_by_one[2])
    run = pickle.loads(pickle.dumps(one_by_one[0]))
    same(run, one_by_one[0])


def test_a_failing_set_is_named(seed):
    with pytest.raises(mechanism.InputError, match="parameter set 1: set: unknown parameter"):
        mechanism.sweep(seed, [SETS[0], {"L2": 0.3}], **OPTIONS)


def ray_or_skip():
    try:
        import ray  # noqa: F401
    except ImportError:
        if os.environ.get("MECHANISM_REQUIRE_RAY"):
            raise
        pytest.skip("ray is not installed (CI installs it and sets MECHANISM_REQUIRE_RAY)")
    return ray


def test_a_ray_sweep_equals_the_runs_one_by_one(seed, one_by_one):
    ray = ray_or_skip()
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        @ray.remote
        def run(model, parameters):
            return model.simulate(set=parameters, **OPTIONS)

        shared = ray.put(seed)
        runs = ray.get([run.remote(shared, s) for s in SETS])
    finally:
        ray.shutdown()
    for r, single in zip(runs, one_by_one):
        same(r, single)
