//! What a refused URDF carries: the file, the line and column of the offending element, the
//! element as written (`<joint name="elbow">`) and what is wrong with it.

use thiserror::Error;

/// A URDF that cannot be imported, or an import option that does not fit it.
///
/// Its `Display` is one line, `FILE:LINE:COL: <joint name="x">: message`, in the form
/// compilers use, so editors can jump to the element. `line` and `column` are 1-based; an
/// error about the options (a `lock` name that names no joint) points at the `<robot>`
/// element.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[error("{file}:{line}:{column}: {}{message}", element_prefix(.element))]
pub struct UrdfError {
    /// The file name given in [`UrdfOptions::file_name`](crate::UrdfOptions::file_name).
    pub file: String,
    /// 1-based line of the offending element (or of the XML syntax error).
    pub line: usize,
    /// 1-based column (in characters) of the offending element.
    pub column: usize,
    /// The element as it opens, with its identifying attribute: `<joint name="elbow">`,
    /// `<mimic joint="finger_1">`, `<inertia>`; empty for an XML syntax error.
    pub element: String,
    /// What is wrong, quoting the URDF's names.
    pub message: String,
}

/// `<element>: ` before the message, or nothing when there is no element.
fn element_prefix(element: &str) -> String {
    if element.is_empty() {
        String::new()
    } else {
        format!("{element}: ")
    }
}

/// Where an element of the URDF is, with its description, kept by the reader so that the
/// checks after it can point back at the element.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Place {
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
    /// The element as it opens (`<link name="hand">`).
    pub element: String,
}

impl Place {
    /// The error `message` at this element of `file`.
    pub fn error(&self, file: &str, message: impl Into<String>) -> UrdfError {
        UrdfError {
            file: file.to_string(),
            line: self.line,
            column: self.column,
            element: self.element.clone(),
            message: message.into(),
        }
    }
}
