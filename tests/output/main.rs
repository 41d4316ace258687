//! Output files: CSV columns and numbers, summary.json keys and values, the figures, the
//! animation page and the strobe figure.

mod scene_support;
mod support;

mod animation;
mod atomic;
mod browser;
mod csv;
mod ownership;
mod plot;
mod summary;
