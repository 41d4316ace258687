//! Prescribed motions written as expressions: `phi = 2*pi*t` becomes a driver constraint
//! q_k - f(t) = 0, with f' and f'' derived symbolically by `mechanism-codegen`.

use mechanism_codegen::{Arena, Differentiator, Matrix, Program, Source, Sources, SymbolKind};

use crate::algorithms::kinematics::Drive;
use crate::error::Error;
use crate::system::System;
use crate::system::routine::{Routine, Values};

/// Why a drive specification was refused.
#[derive(Debug, thiserror::Error)]
pub enum DriveError {
    /// Not of the form `COORD = expression`.
    #[error("a drive is written `COORD = f(t)`, e.g. `phi = 2*pi*t`; got `{0}`")]
    Form(String),
    /// The expression does not parse or differentiate.
    #[error("in the drive `{text}`: {source}")]
    Expression {
        /// The drive text.
        text: String,
        /// The codegen error (boxed: it carries the names a message lists).
        source: Box<mechanism_codegen::Error>,
    },
    /// The runtime refused the drive (an unknown coordinate, for one).
    #[error(transparent)]
    Runtime(#[from] Error),
}

/// Parses `COORD = f(t)` for `system`: f may use t, pi and the mechanism's parameters (at
/// their current values). Returns the [`Drive`] evaluating (f, f', f'').
///
/// # Errors
/// [`DriveError`] naming the problem.
pub fn parse_drive(system: &dyn System, text: &str) -> Result<Drive, DriveError> {
    let (name, expr) = text
        .split_once('=')
        .ok_or_else(|| DriveError::Form(text.to_string()))?;
    // The expression as parsed starts where it starts in `text`, so that a parse error's
    // column counts from the start of the whole drive, as the user wrote it.
    let lead = text[..text.len() - expr.trim_start().len()].chars().count();
    let (name, expr) = (name.trim(), format!("{}{}", " ".repeat(lead), expr.trim()));
    let info = system.info();
    let coordinate = info
        .coordinate_index(name)
        .ok_or_else(|| Error::UnknownCoordinate {
            name: name.to_string(),
            known: info.coordinates.clone(),
        })?;
    let wrap = |source| DriveError::Expression {
        text: text.to_string(),
        source: Box::new(source),
    };
    let mut arena = Arena::new();
    let t = arena.symbol_id("t", SymbolKind::Time);
    let mut values = vec![0.0; info.parameters.len()];
    system.parameter_values(&mut values);
    let params: Vec<_> = info
        .parameters
        .iter()
        .map(|p| arena.symbol_id(p, SymbolKind::Parameter))
        .collect();
    let f = mechanism_codegen::parse_expr(&mut arena, &expr).map_err(wrap)?;
    let mut d = Differentiator::new();
    let f1 = d.diff(&mut arena, f, t).map_err(wrap)?;
    let f2 = d.diff(&mut arena, f1, t).map_err(wrap)?;
    let program = Program::new(&arena, &[&Matrix::column(vec![f, f1, f2])]).map_err(wrap)?;
    let sources: Sources = params
        .iter()
        .enumerate()
        .map(|(k, s)| (*s, Source::Parameter(k)))
        .chain([(t, Source::Time)])
        .collect();
    let routine = Routine::new(&program, &sources, 3).map_err(wrap)?;
    Ok(Drive::new(coordinate, move |time| {
        let at = Values {
            parameters: &values,
            t: time,
            ..Values::default()
        };
        // A non-finite f (e.g. ln of a negative) reaches the output as NaN or infinity,
        // which the solver reports as a non-finite state with its time.
        routine.run(&at, |out| [out[0], out[1], out[2]])
    }))
}
