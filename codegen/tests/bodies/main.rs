//! Bodies, rotations and joints: the grammar, rotation matrices, the RSSR and chains against
//! hand derivations.

mod bodies_chain;
mod bodies_grammar;
mod bodies_rotation;
mod bodies_rssr;
mod links_tree;
