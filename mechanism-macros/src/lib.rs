//! The `mechanism!` proc-macro.
use proc_macro::TokenStream;

/// Declares a mechanism and emits its specialised dynamics code.
#[proc_macro]
pub fn mechanism(input: TokenStream) -> TokenStream {
    let _ = input;
    TokenStream::new()
}
