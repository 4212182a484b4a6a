//! Helpers shared by the command-line tests.
// Each test crate uses its own subset of these.
#![allow(dead_code)]

use std::process::{Child, Command, Output, Stdio};

/// Runs `packbench ARGS` to completion.
pub fn packbench(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_packbench"))
        .args(args)
        .output()
        .expect("runs")
}

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

/// The JSON sidecar `OUT.json` that `packbench pack --output OUT` wrote.
pub fn sidecar(out: &str) -> serde_json::Value {
    let path = format!("{out}.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
}
