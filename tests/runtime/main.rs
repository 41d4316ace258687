//! The runtime checked against independent truth: assembly, loop closure, energy balance,
//! integrators against each other, inverse dynamics, linearisation, overconstrained and
//! singular mechanisms, hand-written systems, the interpreter route, and no allocation in
//! the step loop (this binary counts allocations per thread).

#[global_allocator]
static ALLOCATOR: mechanism_test_support::Counting = mechanism_test_support::Counting;

mod common;

mod assembly;
mod banded_kkt;
mod batch_rows;
mod closure;
mod coordinate_order;
mod coordinate_singularity;
mod dynamics_derivatives;
mod energy;
mod fail_fast;
mod fixed;
mod integrators;
mod interpreted_constraints;
mod interpreted_errors;
mod interpreted_forward;
mod interpreted_tangent;
mod interpreted_threads;
mod inverse;
mod joint_limits;
mod kkt_tree;
mod linearize;
mod linearize_redundant;
mod no_alloc;
mod non_finite;
mod overconstrained;
mod pendulum;
mod portable_math;
mod sparsity;
mod surface_redundancy;
mod systems;
mod tolerance_sweep;
