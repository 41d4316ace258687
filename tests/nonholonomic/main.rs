//! Velocity constraints: rolling wheels, the Whipple bicycle benchmark, the rolling disc and
//! the Chaplygin sleigh, through the interpreter route.

mod bicycle;
mod common;
