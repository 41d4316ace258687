//! `mechanism import`: a URDF robot description as a `.mech` declaration, printed or
//! written to `--out` (under a temporary name, renamed when complete).

use std::path::Path;

use mechanism::output::{OutputError, write_atomically};
use mechanism_codegen::{UrdfOptions, urdf_import};

use super::CliError;
use super::args::ImportArgs;
use super::input::read_input;

/// Runs `mechanism import`. What the import changed from the URDF (an inertia no rigid
/// body has, a clashing name) is noted on stderr, one line each.
///
/// # Errors
/// An `--out` that is the URDF itself (the same file by any path), a path that is not a
/// readable regular file, a file over the input budget
/// ([`super::input`]) or not UTF-8,
/// a URDF the importer refuses (`FILE:LINE:COL: <element>: message`), or a failed write.
pub fn run(args: &ImportArgs) -> Result<(), CliError> {
    if let Some(out) = &args.out {
        check_not_the_input(&args.urdf, out)?;
    }
    let xml = read_urdf(&args.urdf)?;
    let options = UrdfOptions {
        file_name: args.urdf.display().to_string(),
        struct_name: args.name.clone(),
        lock: args.lock.clone(),
        damping: args.damping,
        snap_angles: args.snap_angles,
        floating: args.floating,
    };
    let import = urdf_import(&xml, &options).map_err(|e| CliError::Import(e.to_string()))?;
    // What the import changed from the URDF, one line each (also in the header).
    for note in &import.notes {
        eprintln!("note: {}: {note}", options.file_name);
    }
    let text = import.text;
    match &args.out {
        Some(path) => write_atomically(path, |partial| {
            std::fs::write(partial, &text).map_err(|source| OutputError::Io {
                path: path.clone(),
                source,
            })
        })
        .map_err(CliError::Output),
        // A reader that stops early (`| head`) is not an error of the import.
        None => super::stdio::print(&text),
    }
}

/// The text of the URDF at `path` ([`read_input`]: a regular file within the input budget,
/// in UTF-8).
fn read_urdf(path: &Path) -> Result<String, CliError> {
    read_input(path).map_err(CliError::Import)
}

/// Refuses an `--out` that is the URDF being imported, by any path (`./R.urdf`, a symbolic
/// link, a hard link: the same device and inode), before anything is read or written: the
/// declaration would replace the robot's description.
fn check_not_the_input(urdf: &Path, out: &Path) -> Result<(), CliError> {
    if is_same_file(urdf, out) {
        return Err(CliError::Import(format!(
            "--out {} is the URDF being imported ({}): the declaration would replace it; \
             write it to another file (e.g. --out {})",
            out.display(),
            urdf.display(),
            urdf.with_extension("mech").display()
        )));
    }
    Ok(())
}

/// True when `a` and `b` name one existing file (links followed).
#[cfg(unix)]
fn is_same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// True when `a` and `b` name one existing file (their canonical paths agree).
#[cfg(not(unix))]
fn is_same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}
