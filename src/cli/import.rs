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
/// A path that is not a readable regular file, a file over the input budget
/// ([`super::input`]) or not UTF-8,
/// a URDF the importer refuses (`FILE:LINE:COL: <element>: message`), or a failed write.
pub fn run(args: &ImportArgs) -> Result<(), CliError> {
    let xml = read_urdf(&args.urdf)?;
    let options = UrdfOptions {
        file_name: args.urdf.display().to_string(),
        struct_name: args.name.clone(),
        lock: args.lock.clone(),
        damping: args.damping,
        snap_angles: args.snap_angles,
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
    read_input(path).map_err(|e| CliError::Import(format!("cannot read {}: {e}", path.display())))
}
