//! The `mechanism!` proc-macro: a declared mechanism in, specialised dynamics code out.
//!
//! The pipeline has one stage per file:
//! - `ast`: the input, the declaration's tokens, `file = "mechanisms/x.mech"` or
//!   `urdf = "robot.urdf"` (imported by [`mechanism_codegen::urdf_to_mech`]), parsed into a
//!   [`mechanism_codegen::Model`] with every error mapped to a span;
//! - `check`: the rules the macro adds on top of the parser (one `check_*` per rule);
//! - `generate`: derivation (Lagrange equations with multipliers), CSE and emission of the
//!   method bodies;
//! - `expand`: the struct and the trait impl, `quote!` only (`orientations`: the bodies'
//!   rotation sequences as a constant).
//!
//! See the `mechanism` crate (package `mechanism-dynamics`) for the declaration language
//! (its module `language`) and the trait it implements (`Mechanism`).

mod ast;
mod check;
mod derivatives;
mod dispatch;
mod expand;
mod floating;
mod generate;
mod orientations;
mod robotics;

use proc_macro::TokenStream;

/// Declares a mechanism and emits its specialised dynamics code.
///
/// Either inline, `mechanism! { pub struct Name; parameters { .. } coordinates { .. } .. }`,
/// or from a file relative to `CARGO_MANIFEST_DIR`,
/// `mechanism!(file = "mechanisms/spatial_crank_slider.mech");`, or from a URDF robot
/// description, imported as `mechanism import` does (one `link` per URDF link, gravity
/// 9.81 m/s^2 along -z): `mechanism!(urdf = "robots/arm.urdf", lock = ["finger_joint"],
/// name = Arm);`, where `lock` (joints fixed at q = 0) and `name` (the struct name; default
/// the robot's name in CamelCase) are optional. A URDF the importer refuses is one error at
/// the path, `robots/arm.urdf:12:3: <joint name="x">: message`. The expansion is a struct
/// with one `pub f64` field per parameter and an implementation of `mechanism::Mechanism`.
///
/// The declaration language (grammar, every section and function, what is refused) is the
/// reference page
/// [`mechanism::language`](https://docs.rs/mechanism-dynamics/latest/mechanism/language/index.html);
/// the book's chapter "Declaring a mechanism" (`docs/src/declaring.md`) teaches it by
/// example. An error inside a `.mech` file is reported at the path with the file's line and
/// column and that line quoted:
///
/// ```text
/// error: broken.mech:8:20: parse error: expected a number, a name or `(`, found `;`
///        8 | potential = m*g*y +;
///          |                    ^
/// ```
#[proc_macro]
pub fn mechanism(input: TokenStream) -> TokenStream {
    parse_and_expand(input.into())
        .unwrap_or_else(syn::Error::into_compile_error)
        .into()
}

/// Parses, checks, derives and expands one `mechanism!` invocation: a floating base through
/// [`floating::expand`] (the `FloatingBase` trait), every other through [`expand::expand`].
fn parse_and_expand(input: proc_macro2::TokenStream) -> syn::Result<proc_macro2::TokenStream> {
    let mut decl = ast::parse(input)?;
    check::check(&decl)?;
    if decl.model.floating_root().is_some() {
        floating::expand(&mut decl)
    } else {
        expand::expand(&mut decl)
    }
}
