//! Programs: the compile stage, CSE and instruction selection, emission, the tape, and a
//! tape that allocates nothing (this binary counts allocations per thread).

#[global_allocator]
static ALLOCATOR: mechanism_test_support::Counting = mechanism_test_support::Counting;

mod compile_routines;
mod cse_emit;
mod cse_lowering;
mod cse_tape;
mod cse_tape_alloc;
mod factoring;
