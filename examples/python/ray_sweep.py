"""A tolerance study of the seed paper's spatial crank-slider on a Ray cluster.

Manufacturing tolerances scatter the link lengths h, l1, l2 and d around their nominal
values (normal, standard deviation 0.5 mm); the study asks how far the crank's angle after
2 s of the paper's run spreads across 64 such mechanisms, and which length it is most
sensitive to. Each simulation is a Ray task that takes the model (it pickles to its
declaration text and parameter values) and one parameter set. Run locally:

    pip install ./python ray matplotlib
    python examples/python/ray_sweep.py            # writes ray_sweep.png

`ray.init(num_cpus=2)` starts a local cluster of two workers; on a real cluster,
`ray.init(address="auto")` and nothing else changes. `mechanism.sweep(model, sets)` runs
the same study on one machine without Ray, with the same numbers.
"""

import argparse

import numpy as np
import ray

import mechanism

LENGTHS = ["h", "l1", "l2", "d"]
SIGMA = 0.5e-3  # m


@ray.remote
def crank_angle(model, parameters, t_end):
    """phi(t_end) of one mechanism of the study (rad)."""
    run = model.simulate(t_end=t_end, rtol=1e-9, atol=1e-9, samples_per_second=10.0,
                         set=parameters)
    return run.q[-1, 0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--t-end", type=float, default=2.0)
    ap.add_argument("--out", default="ray_sweep.png")
    args = ap.parse_args()

    seed = mechanism.load("spatial_crank_slider")
    nominal = dict(seed.parameters)
    rng = np.random.default_rng(2026)
    sets = [{name: nominal[name] + SIGMA * rng.standard_normal() for name in LENGTHS}
            for _ in range(args.samples)]

    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        shared = ray.put(seed)  # pickled once, shared by every task
        phi = np.array(ray.get([crank_angle.remote(shared, s, args.t_end) for s in sets]))
        phi0 = ray.get(crank_angle.remote(shared, {}, args.t_end))
    finally:
        ray.shutdown()

    deviations = np.array([[s[name] - nominal[name] for name in LENGTHS] for s in sets])
    # Least-squares sensitivities d phi / d length (rad per mm) from the scatter.
    fit, *_ = np.linalg.lstsq(np.c_[deviations * 1e3, np.ones(len(sets))], phi - phi0,
                              rcond=None)
    print(f"phi({args.t_end:g} s): nominal {phi0:.6f} rad; over {len(sets)} mechanisms "
          f"mean {phi.mean():.6f}, standard deviation {phi.std(ddof=1):.2e} rad")
    for name, slope in zip(LENGTHS, fit[:-1]):
        print(f"  d phi / d {name}: {slope:+.4e} rad/mm")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    axes[0].hist((phi - phi0) * 1e3, bins=16, color="#4477aa")
    axes[0].set_xlabel(f"phi({args.t_end:g} s) - nominal (mrad)")
    axes[0].set_ylabel("mechanisms")
    axes[0].set_title(f"{len(sets)} crank-sliders, lengths +- {SIGMA * 1e3:g} mm (1 sigma)")
    axes[1].bar(LENGTHS, fit[:-1], color="#cc6677")
    axes[1].set_ylabel("d phi / d length (rad/mm)")
    axes[1].set_title("sensitivity (least squares over the scatter)")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
