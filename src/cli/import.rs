//! `mechanism import`: a URDF robot description as a `.mech` declaration, printed or
//! written to `--out` (under a temporary name, renamed when complete).

use std::io::{Read, Write};
use std::path::Path;

use mechanism::output::{OutputError, write_atomically};
use mechanism_codegen::{UrdfOptions, urdf_to_mech};

use super::CliError;
use super::args::ImportArgs;

/// Largest URDF read, bytes (16 MiB: the largest published robot descriptions are a few
/// hundred KB; a larger file is more likely a wrong path than a robot).
pub const MAX_URDF_BYTES: u64 = 16 * 1024 * 1024;

/// Runs `mechanism import`.
///
/// # Errors
/// A path that is not a readable regular file, a file over [`MAX_URDF_BYTES`] or not UTF-8,
/// a URDF the importer refuses (`FILE:LINE:COL: <element>: message`), or a failed write.
pub fn run(args: &ImportArgs) -> Result<(), CliError> {
    let xml = read_urdf(&args.urdf)?;
    let options = UrdfOptions {
        file_name: args.urdf.display().to_string(),
        struct_name: args.name.clone(),
        lock: args.lock.clone(),
    };
    let text = urdf_to_mech(&xml, &options).map_err(|e| CliError::Import(e.to_string()))?;
    match &args.out {
        Some(path) => write_atomically(path, |partial| {
            std::fs::write(partial, &text).map_err(|source| OutputError::Io {
                path: path.clone(),
                source,
            })
        })
        .map_err(CliError::Output),
        None => match std::io::stdout().lock().write_all(text.as_bytes()) {
            // A reader that stops early (`| head`) is not an error of the import.
            Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(CliError::Import(format!(
                "cannot write to standard output: {e}"
            ))),
            _ => Ok(()),
        },
    }
}

/// The text of the URDF at `path`: a regular file (not a folder, a device or a pipe) of at
/// most [`MAX_URDF_BYTES`], in UTF-8.
fn read_urdf(path: &Path) -> Result<String, CliError> {
    let shown = path.display();
    let fail = |what: String| CliError::Import(format!("cannot read {shown}: {what}"));
    let metadata = std::fs::metadata(path).map_err(|e| fail(e.to_string()))?;
    if !metadata.is_file() {
        return Err(fail("not a regular file".into()));
    }
    let too_large = || fail(format!("larger than {} MiB", MAX_URDF_BYTES >> 20));
    if metadata.len() > MAX_URDF_BYTES {
        return Err(too_large());
    }
    let file = std::fs::File::open(path).map_err(|e| fail(e.to_string()))?;
    // The file may grow after its size was read: read one byte past the cap at most.
    let mut bytes = Vec::new();
    file.take(MAX_URDF_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| fail(e.to_string()))?;
    if bytes.len() as u64 > MAX_URDF_BYTES {
        return Err(too_large());
    }
    String::from_utf8(bytes).map_err(|e| {
        fail(format!(
            "not UTF-8 (byte {} is not valid)",
            e.utf8_error().valid_up_to()
        ))
    })
}
