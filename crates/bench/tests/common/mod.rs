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

/// CPU seconds (user + system) that process `pid` has used so far, from /proc; 0 once it is
/// gone. A measure of the process's own progress that a busy machine does not distort.
pub fn cpu_seconds(pid: u32) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
    // Fields after the command name (which may hold spaces) start after the last ')'.
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map(|(_, rest)| rest.split_whitespace().collect())
        .unwrap_or_default();
    let ticks = |k: usize| {
        fields
            .get(k)
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    // utime and stime are fields 14 and 15 of stat, 12 and 13 after the name and state.
    (ticks(11) + ticks(12)) / clock_ticks_per_second()
}

/// The kernel's clock ticks per second (`getconf CLK_TCK`, 100 on Linux), asked once: the
/// wait loops below poll every 20 ms.
fn clock_ticks_per_second() -> f64 {
    static TICKS: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
    *TICKS.get_or_init(|| {
        std::process::Command::new("getconf")
            .arg("CLK_TCK")
            .output()
            .ok()
            .and_then(|o| String::from_utf8(o.stdout).ok()?.trim().parse().ok())
            .unwrap_or(100.0)
    })
}

/// Waits until process `pid` has used `seconds` of CPU: an event of its own work, where a
/// fixed sleep would come early on a busy machine. Panics when the process ends first.
pub fn wait_for_cpu(child: &mut Child, seconds: f64) {
    while cpu_seconds(child.id()) < seconds {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the process ended before using {seconds} s of CPU"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}
