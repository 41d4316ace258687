//! The mechanism library: derived equations pinned by snapshots (reviewed as equations),
//! Andrews' squeezer against the book and the Test Set,
//! the closed chain against its generator, and the body and joint declarations against
//! hand derivations and their energy-declared twins.

mod andrews_squeezer;
mod bodies_dynamics;
mod bodies_inline;
mod bodies_joints;
mod bodies_snapshots;
mod chain_pinocchio;
mod closed_chain;
mod derivatives_pinocchio;
mod drawing;
mod floating_derivatives;
mod floating_interpreted;
mod floating_motion;
mod floating_pinocchio;
mod g1_pinocchio;
mod links_robot;
mod panda_pinocchio;
mod snapshots;
mod urdf_damping;
mod urdf_mimic;
mod urdf_snap;
