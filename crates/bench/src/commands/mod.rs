//! One module per subcommand. Each returns what to print; `main` prints it.

pub mod analyze;
pub mod animate;
pub mod compare;
pub mod design;
pub mod export;
pub mod init;
pub mod merge;
pub mod pack;
pub mod plot;
pub mod predict;
pub mod reproduce;
pub mod sweep;
pub mod view;

/// What a command wants printed.
#[derive(Default)]
pub struct Printed {
    /// For standard output (the command's product when no file was asked for).
    pub stdout: String,
    /// Notes for standard error (seeds, where files went).
    pub stderr: Vec<String>,
}
