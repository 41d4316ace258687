//! The animation page in a real browser: headless Chromium loads animation.html from disk,
//! the page reports no error, and screenshots at two times differ where the mechanism
//! moved (and are identical at the same time, so the difference is the motion).
//!
//! Needs Chromium (`apt-get install chromium`), so it is ignored by a plain `cargo test`,
//! which lists it as ignored with the reason; `.ci/run` installs Chromium and runs it with
//! `cargo test --test output -- --ignored`, where a missing browser is a failure.

use std::path::{Path, PathBuf};
use std::process::Command;

use mechanism::output::write_animation;

use crate::scene_support::four_bar_scene;
use crate::support::temp_dir;

/// The Chromium binary: $CHROMIUM, or the first of the usual names on PATH.
fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |d| d.join(name)))
        .find(|p| p.is_file())
}

/// Runs headless Chromium on `page#hash` with `args`; returns stdout.
fn run(browser: &Path, profile: &Path, page: &Path, hash: &str, args: &[&str]) -> String {
    let url = format!("file://{}#{hash}", page.display());
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(["--window-size=1280,900", "--virtual-time-budget=3000"])
        .args(args)
        .arg(url)
        .output()
        .expect("chromium runs");
    assert!(
        out.status.success(),
        "chromium failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// RGBA pixels and width of a PNG file.
fn pixels(path: &Path) -> (Vec<u8>, usize) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    let channels = info.color_type.samples();
    let rgba = buf
        .chunks_exact(channels)
        .flat_map(|c| [c[0], c[1 % channels], c[2 % channels], 255])
        .collect();
    (rgba, info.width as usize)
}

/// A rectangle of pixels: x range, y range.
type Region = ((usize, usize), (usize, usize));

/// Pixels that differ inside `region`.
fn differing(a: &(Vec<u8>, usize), b: &(Vec<u8>, usize), (xs, ys): Region) -> usize {
    let w = a.1;
    (ys.0..ys.1)
        .flat_map(|y| (xs.0..xs.1).map(move |x| 4 * (y * w + x)))
        .filter(|&o| a.0[o..o + 3] != b.0[o..o + 3])
        .count()
}

#[test]
#[ignore = "needs headless Chromium (apt-get install chromium); run: cargo test --test output -- --ignored"]
fn the_page_runs_in_chromium_and_shows_the_motion() {
    let browser = chromium()
        .expect("no Chromium found: apt-get install chromium, or set CHROMIUM to its path");
    let dir = temp_dir("browser");
    let page = dir.join("animation.html");
    write_animation(&page, &four_bar_scene(201)).unwrap();
    let profile = dir.join("profile");

    let dom = run(&browser, &profile, &page, "t=0.2", &["--dump-dom"]);
    assert!(
        dom.contains("data-status=\"ok\""),
        "the page did not report ok: {}",
        &dom[..dom.len().min(300)]
    );
    assert!(
        dom.contains("t = 0.200 s"),
        "the clock shows the requested time"
    );

    let shot = |hash: &str, name: &str| {
        let file = dir.join(name);
        run(
            &browser,
            &profile,
            &page,
            hash,
            &[&format!("--screenshot={}", file.display())],
        );
        pixels(&file)
    };
    let (a, a_again, b) = (
        shot("t=0.2", "a.png"),
        shot("t=0.2", "a2.png"),
        shot("t=0.7", "b.png"),
    );
    // The view canvas: the left column below the header (the clock, slider and plots are
    // in the right column at this window width).
    let view = ((20, 600), (90, 560));
    assert_eq!(
        differing(&a, &a_again, view),
        0,
        "the same time draws the same picture"
    );
    let moved = differing(&a, &b, view);
    assert!(
        moved > 2000,
        "only {moved} pixels of the view changed between t = 0.2 and 0.7 s"
    );
}
