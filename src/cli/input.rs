//! Reading an input file (a `.mech` declaration, a URDF) with limits: only a regular file,
//! and at most [`MAX_INPUT_BYTES`] of it.
//!
//! A FIFO would block the read until a writer comes (forever, if none does), and a device
//! such as `/dev/zero` (or a symbolic link to one) never ends: both are refused before they
//! are opened. The size is checked twice, before reading and while reading (a file may
//! grow in between), so no more than the limit plus one byte is ever held.

use std::io::Read as _;
use std::path::Path;

/// Largest input file read, bytes: 16 MiB. The largest declarations we know (the Panda's
/// URDF, the 32-bar chain) are under 100 KB, and a declaration of 20 MB takes about 70 s
/// and 2 GB to derive; a larger file is far more likely a wrong path than a mechanism.
/// Raised by the environment variable `MECHANISM_MAX_INPUT_BYTES`.
pub const MAX_INPUT_BYTES: u64 = 16 * 1024 * 1024;

/// [`MAX_INPUT_BYTES`], or `MECHANISM_MAX_INPUT_BYTES` when set.
///
/// # Errors
/// The variable set to anything but a positive whole number (as the derivation's
/// `MECHANISM_MAX_*` variables are refused): a typo must not leave the limit silently
/// where it was.
pub fn input_budget() -> Result<u64, String> {
    match std::env::var("MECHANISM_MAX_INPUT_BYTES") {
        Err(_) => Ok(MAX_INPUT_BYTES),
        Ok(v) => match v.trim().parse::<u64>() {
            Ok(bytes) if bytes > 0 => Ok(bytes),
            _ => Err(format!(
                "MECHANISM_MAX_INPUT_BYTES must be a positive whole number of bytes, got `{v}`"
            )),
        },
    }
}

/// The text of the file at `path` (see the module docs); the error is one line naming the
/// file: `cannot read <path>: <reason>`, or `<path>:<line>:<column>: ...` for a byte that
/// is not UTF-8.
pub fn read_input(path: &Path) -> Result<String, String> {
    let cannot = |reason: String| format!("cannot read {}: {reason}", path.display());
    let metadata = std::fs::metadata(path).map_err(|e| cannot(e.to_string()))?;
    if !metadata.is_file() {
        return Err(cannot(format!("not a regular file ({})", kind(&metadata))));
    }
    let budget = input_budget().map_err(cannot)?;
    let too_large = |size: u64| {
        cannot(format!(
            "{size} bytes, more than the {budget} allowed for an input file; raise the limit \
             with the environment variable MECHANISM_MAX_INPUT_BYTES={size}"
        ))
    };
    if metadata.len() > budget {
        return Err(too_large(metadata.len()));
    }
    let file = std::fs::File::open(path).map_err(|e| cannot(e.to_string()))?;
    let mut bytes = Vec::new();
    file.take(budget + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| cannot(e.to_string()))?;
    if bytes.len() as u64 > budget {
        return Err(too_large(bytes.len() as u64));
    }
    decode(path, bytes)
}

/// `bytes` read from `path` as UTF-8 text. UTF-16 (with its byte-order mark, or ASCII text
/// with every other byte zero) is named as such, with the conversion to run; another byte
/// that is not UTF-8 is located by its offset, line and column (of the text before it), as
/// an editor counts them.
fn decode(path: &Path, bytes: Vec<u8>) -> Result<String, String> {
    let p = path.display();
    if let Some((order, encoding)) = utf16(&bytes) {
        return Err(format!(
            "cannot read {p}: it is UTF-16 text ({order}), and input files are read as UTF-8: \
             convert it, e.g. `iconv -f {encoding} -t UTF-8 {p} > utf8-copy`"
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let bytes = e.as_bytes();
        // The bytes before `at` are valid UTF-8: count its lines and characters.
        let before = std::str::from_utf8(&bytes[..at]).unwrap_or_default();
        let line = before.matches('\n').count() + 1;
        let column = before
            .rsplit('\n')
            .next()
            .unwrap_or_default()
            .chars()
            .count()
            + 1;
        format!(
            "{p}:{line}:{column}: byte {at} (0x{:02x}) is not valid UTF-8: save the file as \
             UTF-8 (from Latin-1, e.g. `iconv -f LATIN1 -t UTF-8 {p} > utf8-copy`)",
            bytes[at]
        )
    })
}

/// Which UTF-16 `bytes` look like, if any, and its name for `iconv`: a byte-order mark, or
/// (without one) an ASCII first character with a zero byte beside it, which UTF-8 text
/// never starts with.
fn utf16(bytes: &[u8]) -> Option<(&'static str, &'static str)> {
    match bytes {
        [0xff, 0xfe, ..] => Some((
            "little-endian, its byte-order mark FF FE at byte 0",
            "UTF-16",
        )),
        [0xfe, 0xff, ..] => Some(("big-endian, its byte-order mark FE FF at byte 0", "UTF-16")),
        [a, 0, ..] if a.is_ascii() && *a != 0 => {
            Some(("little-endian, without a byte-order mark", "UTF-16LE"))
        }
        [0, b, ..] if b.is_ascii() && *b != 0 => {
            Some(("big-endian, without a byte-order mark", "UTF-16BE"))
        }
        _ => None,
    }
}

/// What a file that is not a regular one is: a folder, a pipe, a device.
fn kind(metadata: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        let t = metadata.file_type();
        if t.is_fifo() {
            return "a pipe";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if metadata.is_dir() {
        "a folder"
    } else {
        "not a file"
    }
}
