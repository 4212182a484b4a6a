//! Random malformed packing files against `analyze` and `pack --file`: every file either works
//! or is refused with exit 2 and one located sentence, never a panic, a hang or a file left
//! behind. The files mix well-formed rows with the damage real files carry: wrong column
//! counts, words, NaN and infinities, huge and tiny values, negative or zero diameters,
//! commas, comments, blank lines, byte-order marks, NUL bytes and invalid UTF-8.

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use proptest::prelude::*;

/// Longest a command may take on one of these files (at most 12 particles) before it counts
/// as a hang.
const HANG_AFTER: Duration = Duration::from_secs(60);

/// One token of a row: usually a plausible coordinate or diameter, sometimes damage.
fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        6 => (0.0..1.0f64).prop_map(|v| format!("{v}")),
        2 => (0.01..0.3f64).prop_map(|v| format!("{v:e}")),
        1 => Just("nan".to_string()),
        1 => Just("-inf".to_string()),
        1 => Just("1e308".to_string()),
        1 => Just("1e-320".to_string()),
        1 => Just("-0.2".to_string()),
        1 => Just("0".to_string()),
        1 => Just("abc".to_string()),
        1 => Just("0x1p3".to_string()),
        1 => Just("1,".to_string()),
        1 => Just("\u{feff}0.5".to_string()),
        1 => Just("0.\u{0}5".to_string()),
        1 => Just("é".to_string()),
    ]
}

/// One line: a row of 1 to 20 tokens, a comment or a blank line.
fn line() -> impl Strategy<Value = String> {
    prop_oneof![
        8 => prop::collection::vec(token(), 1..=20).prop_flat_map(|t| {
            prop_oneof![Just(t.join(" ")), Just(t.join(",")), Just(t.join("\t"))]
        }),
        3 => (0.05..0.95f64, 0.05..0.95f64, 0.02..0.2f64)
            .prop_map(|(x, y, d)| format!("{x} {y} {d}")),
        3 => (0.05..0.95f64, 0.05..0.95f64, 0.05..0.95f64, 0.02..0.2f64)
            .prop_map(|(x, y, z, d)| format!("{x} {y} {z} {d}")),
        1 => Just("# a comment".to_string()),
        1 => Just(String::new()),
    ]
}

/// A whole file: up to 12 lines, sometimes with a BOM, invalid UTF-8 or no final newline.
fn file_bytes() -> impl Strategy<Value = Vec<u8>> {
    (prop::collection::vec(line(), 0..12), any::<bool>(), 0u8..4).prop_map(
        |(lines, newline_at_end, extra)| {
            let mut text = lines.join("\n");
            if newline_at_end {
                text.push('\n');
            }
            let mut bytes = text.into_bytes();
            match extra {
                1 => bytes.splice(0..0, "\u{feff}".bytes()).for_each(drop),
                2 => bytes.extend_from_slice(&[0xff, 0xfe, b'\n']),
                _ => {}
            }
            bytes
        },
    )
}

/// Runs `packbench ARGS`, killing it if it runs longer than `HANG_AFTER`.
fn run(args: &[&str]) -> Result<Output, String> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_packbench"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| e.to_string())?;
    let started = Instant::now();
    while child.try_wait().map_err(|e| e.to_string())?.is_none() {
        if started.elapsed() > HANG_AFTER {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("{args:?} ran longer than {HANG_AFTER:?}"));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().map_err(|e| e.to_string())
}

/// Exit 0, or exit 2 with one sentence on stderr (naming the file when it points into it);
/// never a panic.
fn worked_or_refused(o: &Output, file: &Path) -> Result<(), String> {
    let err = String::from_utf8_lossy(&o.stderr);
    if err.contains("panicked") {
        return Err(format!("panic: {err}"));
    }
    match o.status.code() {
        Some(0) => Ok(()),
        Some(2) if err.trim().lines().count() == 1 => {
            let name = file.file_name().unwrap().to_string_lossy();
            let located = err.contains(":1:") || err.contains(":2:") || err.contains(":3:");
            if o.stderr.contains(&0) {
                Err(format!("a NUL byte was echoed: {err}"))
            } else if located && !err.contains(name.as_ref()) {
                Err(format!("a located refusal does not name the file: {err}"))
            } else {
                Ok(())
            }
        }
        code => Err(format!("exit {code:?}: {err}")),
    }
}

/// Names in `dir` besides the input file.
fn written(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "in.txt")
        .collect()
}

fn case_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir()
        .join("packbench-malformed")
        .join(format!("{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn analyze_takes_or_refuses_any_file(bytes in file_bytes(), with_box in any::<bool>()) {
        let dir = case_dir("analyze");
        let file = dir.join("in.txt");
        std::fs::write(&file, &bytes).unwrap();
        let path = file.display().to_string();
        let mut args = vec!["analyze", path.as_str()];
        if with_box {
            args.extend(["--box", "1,1,1"]);
        }
        let o = run(&args).map_err(TestCaseError::fail)?;
        worked_or_refused(&o, &file).map_err(TestCaseError::fail)?;
        prop_assert!(written(&dir).is_empty(), "analyze wrote {:?}", written(&dir));
    }

    #[test]
    fn pack_takes_or_refuses_any_file(bytes in file_bytes()) {
        let dir = case_dir("pack");
        let file = dir.join("in.txt");
        std::fs::write(&file, &bytes).unwrap();
        let path = file.display().to_string();
        let out = dir.join("out").display().to_string();
        let o = run(&[
            "pack", "--method", "adam", "--file", &path, "--seed", "1", "--quiet",
            "--no-force-balance", "--output", &out,
        ])
        .map_err(TestCaseError::fail)?;
        worked_or_refused(&o, &file).map_err(TestCaseError::fail)?;
        let mut names = written(&dir);
        names.sort();
        if o.status.success() {
            prop_assert_eq!(names, vec!["out.json".to_string(), "out.txt".to_string()]);
        } else {
            prop_assert!(names.is_empty(), "a refused run left {:?}", names);
        }
    }
}
