//! What `mechanism!` emits: the same routines and numbers as the interpreter route, large
//! declarations, and generated code that allocates nothing (this binary counts allocations
//! per thread).

#[global_allocator]
static ALLOCATOR: mechanism_test_support::Counting = mechanism_test_support::Counting;

mod dispatch_copies;
mod emitted_bits;
mod emitted_vs_interpreter;
mod file_paths;
mod initial_values;
mod large_mechanism;
mod no_alloc;
mod one_routines;
mod parameter_cache;
mod pass_cases;
