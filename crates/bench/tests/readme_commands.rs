//! README's shell blocks, run as a newcomer runs them: top to bottom in one empty folder, each
//! after the ones above it, with `packbench` the binary under test. A command that fails, or
//! refers to a file no earlier command made, fails this test.
//!
//! The one substitution, so the whole README runs in a few minutes: every number after `--N`
//! above [`SMALL_N`] becomes `SMALL_N` (except in a `reproduce` line that already asks for no
//! more than [`TABLE_MIN_N`], a table's own smallest N), and every `--seeds` above
//! [`FEW_SEEDS`] becomes `FEW_SEEDS`. `cargo run --release -p packbench --` is the binary itself. Left out: blocks
//! with `#SBATCH` lines (tests/slurm/run.sh runs them under Slurm) and the line that runs
//! `scripts/test-all` (the suite this test is part of).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// Largest N a README command runs with here (reproduce baranau2014-table4 takes no fewer than 100).
const SMALL_N: u64 = 100;
/// Most starting packings a README command runs with here.
const FEW_SEEDS: u64 = 2;
/// The largest of the smallest N a `reproduce` table holds (`dimensions`: 250); a README
/// `reproduce` line asking for at most this many keeps its N.
const TABLE_MIN_N: u64 = 250;

/// The ```bash blocks of `markdown`, in order.
fn shell_blocks(markdown: &str) -> Vec<String> {
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in markdown.lines() {
        match (&mut current, line.trim_start()) {
            (None, l) if l == "```bash" || l == "```sh" => current = Some(String::new()),
            (Some(block), "```") => {
                blocks.push(std::mem::take(block));
                current = None;
            }
            (Some(block), _) => {
                block.push_str(line);
                block.push('\n');
            }
            _ => {}
        }
    }
    blocks
}

/// `line` with the substitution of the module's rule applied.
fn small(line: &str) -> String {
    let line = line.replace("cargo run --release -p packbench --", "packbench");
    let mut words: Vec<String> = line.split(' ').map(String::from).collect();
    let reproduce = words.iter().any(|w| w == "reproduce");
    for k in 1..words.len() {
        let cap = match words[k - 1].as_str() {
            "--N" => SMALL_N,
            "--seeds" => FEW_SEEDS,
            _ => continue,
        };
        if let Ok(v) = words[k].parse::<u64>() {
            let kept = reproduce && cap == SMALL_N && v <= TABLE_MIN_N;
            words[k] = if kept { v } else { v.min(cap) }.to_string();
        }
    }
    words.join(" ")
}

/// The script a block becomes: the rule applied, the test-suite line left out.
fn script(block: &str) -> String {
    block
        .lines()
        .filter(|l| !l.trim_start().starts_with("scripts/test-all"))
        .map(small)
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn the_substitution_rule_shrinks_only_n_and_seeds() {
    assert_eq!(
        small("packbench compare --N 1000 --Ndim 3 --seeds 10 --seed 1"),
        "packbench compare --N 100 --Ndim 3 --seeds 2 --seed 1"
    );
    assert_eq!(
        small("packbench init --N 40 --phi 0.05"),
        "packbench init --N 40 --phi 0.05"
    );
    assert_eq!(
        small("packbench reproduce dimensions --N 250 --seeds 3"),
        "packbench reproduce dimensions --N 250 --seeds 2"
    );
    assert_eq!(
        small("packbench reproduce baranau2014-table4 --N 1000"),
        "packbench reproduce baranau2014-table4 --N 100"
    );
    assert_eq!(
        small("cargo run --release -p packbench -- compare"),
        "packbench compare"
    );
    let md = "text\n```bash\na\nb\n```\n```python\nc\n```\n```bash\nd\n```\n";
    assert_eq!(shell_blocks(md), ["a\nb\n", "d\n"]);
}

#[test]
fn every_readme_command_runs_in_order() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let readme = std::fs::read_to_string(root.join("README.md")).expect("README.md");
    let bin = Path::new(env!("CARGO_BIN_EXE_packbench"));
    let path = format!(
        "{}:{}",
        bin.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let dir = std::env::temp_dir().join(format!("packbench-readme-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let blocks: Vec<String> = shell_blocks(&readme)
        .into_iter()
        .filter(|b| !b.contains("#SBATCH"))
        .collect();
    assert!(
        blocks.len() >= 4,
        "README has {} shell blocks",
        blocks.len()
    );
    for (k, block) in blocks.iter().enumerate() {
        let script = script(block);
        let t0 = Instant::now();
        let out = Command::new("bash")
            .args(["-euxo", "pipefail", "-c", &script])
            .current_dir(&dir)
            .env("PATH", &path)
            .output()
            .expect("bash runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        eprintln!(
            "README block {} of {}: {:.1} s",
            k + 1,
            blocks.len(),
            t0.elapsed().as_secs_f64()
        );
        assert!(
            out.status.success(),
            "README block {} failed ({}):\n{script}\n--- stderr (the last command is the failing one):\n{}",
            k + 1,
            out.status,
            stderr
                .lines()
                .rev()
                .take(30)
                .collect::<Vec<_>>()
                .into_iter()
                .rev()
                .collect::<Vec<_>>()
                .join("\n")
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
