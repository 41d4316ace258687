//! The mechanism itself in the output folder: `animation.html` (the moving mechanism with
//! the coordinate plots) and the strobe figure `mechanism.png` / `.svg`, for any command
//! whose mechanism declares a `draw` section.

use std::path::{Path, PathBuf};

use super::args::{CommonArgs, ViewArg};
use mechanism::System;
use mechanism::output::{MAX_FRAMES, OutputError, Scene, View, plot_strobe, write_animation};

/// Writes the animation page and the strobe figure of the states `state(i)`, i < `samples`,
/// into `dir`; returns the files written (none when the mechanism draws nothing or
/// `--no-animation` is given).
pub fn write_drawing<'a>(
    system: &dyn System,
    common: &CommonArgs,
    dir: &Path,
    samples: usize,
    state: impl Fn(usize) -> (f64, &'a [f64]),
) -> Result<Vec<PathBuf>, OutputError> {
    if common.no_animation {
        return Ok(vec![]);
    }
    let Some(scene) = Scene::from_samples(system, samples, MAX_FRAMES, state) else {
        return Ok(vec![]);
    };
    let page = dir.join("animation.html");
    write_animation(&page, &scene)?;
    let view = match common.view {
        ViewArg::Auto => View::Auto,
        ViewArg::Xy => View::Xy,
        ViewArg::Xz => View::Xz,
        ViewArg::Yz => View::Yz,
        ViewArg::Oblique => View::Oblique,
    };
    let mut files = vec![page];
    files.extend(plot_strobe(
        &dir.join("mechanism"),
        &scene,
        view,
        common.strobe as usize,
    )?);
    Ok(files)
}
