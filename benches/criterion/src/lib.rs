//! Empty: the benches are `benches/{derivation,evaluation,simulation}.rs` (a package needs
//! a library or a binary).
