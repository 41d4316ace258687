//! The figures' font: DejaVu Sans, bundled (its licence: assets/fonts/DejaVu-LICENSE.txt),
//! registered with plotters as `sans-serif`, so every figure looks the same on every
//! machine.

use std::sync::OnceLock;

use plotters::style::FontStyle;

/// The family name the figures ask plotters for.
pub(super) const FONT: &str = "sans-serif";
/// The font file.
pub(super) const FONT_BYTES: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

/// Registers the bundled DejaVu Sans as plotters' `sans-serif`, once per process.
pub(super) fn register_font() -> Result<(), String> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    DONE.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES)
            .map_err(|_| "invalid bundled font".to_string())
    })
    .clone()
}
