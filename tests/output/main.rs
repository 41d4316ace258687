//! Output files: CSV columns and numbers, summary.json keys and values, the figures.

mod support;

mod atomic;
mod csv;
mod plot;
mod summary;
