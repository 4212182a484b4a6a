//! Helpers shared by the command-line tests.

use std::process::{Child, Command, Stdio};

/// Starts `packbench ARGS OUT` in the background (stdout discarded, stderr captured), for tests
/// that signal a running command.
pub fn spawn_packbench(args: &str, out: &str) -> Child {
    Command::new(env!("CARGO_BIN_EXE_packbench"))
        .args(args.split_whitespace())
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs")
}
