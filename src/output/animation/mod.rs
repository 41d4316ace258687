//! `animation.html`: one self-contained page (no network at view time: the viewer script,
//! its style and the data are inline) that shows the mechanism moving in 3D, with orbit,
//! pan and zoom, play, pause, speed and a time slider, traces of chosen points, and the
//! coordinate plots with a cursor that follows the animation.
//!
//! The page draws a [`Scene`] built with at most [`MAX_FRAMES`] frames and at most
//! [`MAX_VALUES`](super::MAX_VALUES) numbers: a long run, or a large mechanism's, is
//! decimated (every k-th sample, and always the last), so the page stays under about 1.5 MB
//! whatever the run's length and the mechanism's size.

use std::path::Path;

use super::OutputError;
use super::scene::Scene;

/// Most frames a page holds (a 60 s run at 25 frames per second).
pub const MAX_FRAMES: usize = 1500;

const PAGE: &str = include_str!("page.html");
const STYLE: &str = include_str!("style.css");
const SCRIPT: &str = include_str!("viewer.js");

/// The page for `scene` as one HTML string: style, script and data inline.
pub fn animation_html(scene: &Scene) -> Result<String, OutputError> {
    let data = serde_json::to_string(scene).map_err(|source| OutputError::Json {
        path: "animation.html".into(),
        source,
    })?;
    // JSON inside <script>: "</" must not close the element early.
    let data = data.replace("</", "<\\/");
    let title = format!("{}: animation", escape_html(&scene.name));
    Ok(PAGE
        .replace("__TITLE__", &title)
        .replace("__STYLE__", STYLE)
        .replace("__SCRIPT__", SCRIPT)
        .replace("__DATA__", &data))
}

/// Writes [`animation_html`] of `scene` to `path` (whole or not at all), creating its
/// directory.
pub fn write_animation(path: &Path, scene: &Scene) -> Result<(), OutputError> {
    let html = animation_html(scene)?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        super::ensure_dir(dir)?;
    }
    // Under a temporary name, renamed when complete (see `output::atomic`).
    super::write_atomically(path, |partial| {
        std::fs::write(partial, &html).map_err(|e| OutputError::io(path, e))
    })
}

/// `<`, `>`, `&` and `"` as entities.
fn escape_html(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
