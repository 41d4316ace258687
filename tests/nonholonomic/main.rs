//! Velocity constraints: rolling wheels, the Whipple bicycle benchmark, the rolling disc and
//! the Chaplygin sleigh, through the interpreter route (the bicycle through `mechanism!` too).

mod bicycle;
mod bicycle_run;
mod common;
mod dependent_rows;
mod disc;
mod errors;
mod inverse_rolling;
mod macro_route;
mod sleigh;
