//! Result files are written whole or not at all (a temporary `.<stem>.partial.<ext>` renamed
//! when complete, removed when the write fails or panics), and a new run removes exactly the
//! files the previous run's summary.json listed, if that summary is ours.

use std::path::Path;

use crate::support::{files_in, set, temp_dir, time, trajectory};
use mechanism::output::{
    OutputError, Unit, plot_coordinate, remove_previous_results, temporary_path, write_atomically,
    write_trajectory_csv,
};

#[test]
fn the_temporary_keeps_the_folder_and_the_extension() {
    let p = temporary_path(Path::new("out/seed/fig_3_1_phi.png"));
    assert_eq!(p, Path::new("out/seed/.fig_3_1_phi.partial.png"));
    assert_eq!(
        temporary_path(Path::new("summary.json")),
        Path::new(".summary.partial.json")
    );
}

#[test]
fn a_write_replaces_the_file_only_when_complete() {
    let dir = temp_dir("atomic");
    let target = dir.join("data.txt");
    std::fs::write(&target, "old").unwrap();
    // Success: renamed over the target.
    write_atomically(&target, |p| {
        std::fs::write(p, "new").map_err(|e| OutputError::Io {
            path: p.to_path_buf(),
            source: e,
        })
    })
    .unwrap();
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "new");
    // An error after part of the file: the target keeps its content, no temporary stays.
    let err = write_atomically(&target, |p| {
        std::fs::write(p, "half").unwrap();
        Err::<(), _>(OutputError::InvalidData {
            what: "data".into(),
            message: "disk full".into(),
        })
    });
    assert!(err.is_err());
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "new");
    // A panic while writing: the same.
    let panicked = std::panic::catch_unwind(|| {
        write_atomically(&target, |p| -> Result<(), OutputError> {
            std::fs::write(p, "half").unwrap();
            panic!("drawing failed")
        })
    });
    assert!(panicked.is_err());
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "new");
    assert_eq!(files_in(&dir), set(&["data.txt"]));
}

#[test]
fn a_csv_that_fails_midway_leaves_the_previous_one() {
    let dir = temp_dir("atomic-csv");
    let path = dir.join("trajectory.csv");
    write_trajectory_csv(&path, &trajectory("x")).unwrap();
    let before = std::fs::read(&path).unwrap();
    // A table whose third row is short fails after two rows are written.
    let header = vec!["t".to_string(), "x".to_string()];
    let rows: [&[f64]; 3] = [&[0.0, 1.0], &[0.1, 2.0], &[0.2]];
    let err = mechanism::output::csv::write_table(&path, &header, rows).expect_err("short row");
    assert!(matches!(err, OutputError::InvalidData { .. }), "{err}");
    assert_eq!(std::fs::read(&path).unwrap(), before, "untouched");
    assert_eq!(files_in(&dir), set(&["trajectory.csv"]));
}

#[test]
fn a_figure_that_cannot_be_placed_leaves_no_temporary() {
    let dir = temp_dir("atomic-plot");
    // A folder where the PNG should go: the rename fails after the drawing.
    std::fs::create_dir(dir.join("x.png")).unwrap();
    let t: Vec<f64> = (0..50).map(time).collect();
    let y: Vec<f64> = t.iter().map(|t| t.sin()).collect();
    let err = plot_coordinate(&dir.join("x"), "x", Unit::Length, &t, &y, &y);
    assert!(err.is_err());
    assert_eq!(files_in(&dir), set(&["x.png"]));
    // Where it can, both files are complete and nothing else is left.
    let written = plot_coordinate(&dir.join("y"), "y", Unit::Length, &t, &y, &y).unwrap();
    assert_eq!(written.len(), 2);
    assert_eq!(files_in(&dir), set(&["x.png", "y.png", "y.svg"]));
}

#[test]
fn only_the_files_the_previous_summary_lists_are_removed() {
    let dir = temp_dir("previous");
    for f in [
        "trajectory.csv",
        "phi.png",
        "notes.txt",
        ".phi.partial.svg",
        "keep.partial.csv",
    ] {
        std::fs::write(dir.join(f), "x").unwrap();
    }
    std::fs::create_dir(dir.join("plots")).unwrap();
    let outside = dir.parent().unwrap().join(format!(
        "outside-{}",
        dir.file_name().unwrap().to_string_lossy()
    ));
    std::fs::write(&outside, "not ours").unwrap();
    let escape = format!("../{}", outside.file_name().unwrap().to_string_lossy());
    let summary = serde_json::json!({
        "format": "mechanism-summary",
        "format_version": 1,
        "status": "completed",
        "files": ["trajectory.csv", "summary.json", "phi.png", "missing.svg", "plots",
                  escape, "/etc/hostname", "a/b"],
    });
    std::fs::write(dir.join("summary.json"), summary.to_string()).unwrap();
    let removed = remove_previous_results(&dir).unwrap();
    assert_eq!(removed.len(), 4, "{removed:?}");
    assert_eq!(
        files_in(&dir),
        set(&["notes.txt", "keep.partial.csv", "plots"])
    );
    assert!(
        outside.is_file(),
        "a listed path outside the folder is never removed"
    );
    std::fs::remove_file(outside).unwrap();
    // Nothing to do in a folder without a summary, or one that does not exist.
    assert!(remove_previous_results(&dir).unwrap().is_empty());
    assert!(
        remove_previous_results(&dir.join("nonesuch"))
            .unwrap()
            .is_empty()
    );
}

#[test]
fn a_summary_we_did_not_write_removes_nothing() {
    // Another tool's summary, an empty one, one of ours from before the format mark, and
    // one of a format version we do not know: none is trusted.
    let foreign = [
        r#"{"files": ["thesis.tex", "inverse.csv"]}"#,
        "{}",
        r#"{"status": "completed", "files": ["thesis.tex", "inverse.csv"]}"#,
        r#"{"format": "mechanism-summary", "format_version": 2, "files": ["thesis.tex"]}"#,
        r#"{"format": "other", "format_version": 1, "files": ["thesis.tex"]}"#,
    ];
    for text in foreign {
        let dir = temp_dir("previous-foreign");
        for f in ["thesis.tex", "inverse.csv", "phi.png"] {
            std::fs::write(dir.join(f), "x").unwrap();
        }
        std::fs::write(dir.join("summary.json"), text).unwrap();
        assert!(remove_previous_results(&dir).unwrap().is_empty(), "{text}");
        assert_eq!(
            files_in(&dir),
            set(&["thesis.tex", "inverse.csv", "phi.png", "summary.json"]),
            "{text}"
        );
    }
}
