//! `packbench animate`: a run as an animated GIF for slides, frame by frame from its
//! `--save-interval` snapshots to its final packing: 2D disks to scale, or in 3D and up the
//! slice through the middle, with φ in the corner (the same drawing as `packbench plot`).

use std::path::PathBuf;

use clap::Args;
use plotters::prelude::*;

use super::Printed;
use crate::error::{BenchError, usage};
use crate::figures::draw_packing;
use crate::viewer::{read_run, thin};

/// Flags of `packbench animate`.
#[derive(Args, Debug)]
pub struct AnimateArgs {
    /// The run: its packing NAME.txt or sidecar NAME.json, with NAME_step<K>.txt snapshots
    /// (`packbench pack --save-interval K --output NAME`).
    pub file: PathBuf,
    /// The GIF to write (default NAME.gif).
    #[arg(long)]
    pub output: Option<PathBuf>,
    /// Width and height of the frames in pixels.
    #[arg(long, default_value_t = 480)]
    pub size: u32,
    /// Time each frame is shown, in milliseconds (the final packing is held 2 s).
    #[arg(long = "delay-ms", default_value_t = 150)]
    pub delay_ms: u32,
    /// Most frames (evenly spread over the snapshots, the final packing always kept).
    #[arg(long = "max-frames", default_value_t = 80)]
    pub max_frames: usize,
}

/// One frame of the GIF: its title, how long it is shown (ms) and its packing.
type GifFrame<'a> = (String, u32, &'a packbench_core::Packing);

/// Draws `frames` into a GIF at `path`, `size` pixels square, `delay_ms` per frame.
fn draw_gif(
    path: &std::path::Path,
    size: u32,
    delay_ms: u32,
    frames: &[GifFrame<'_>],
) -> Result<(), Box<dyn std::error::Error>> {
    // plotters sets one delay for the whole GIF; a longer hold repeats the frame.
    let root = BitMapBackend::gif(path, (size, size), delay_ms)?.into_drawing_area();
    for (title, hold, p) in frames {
        for _ in 0..(hold / delay_ms).max(1) {
            draw_packing(&root, p, title)?;
            root.present()?;
        }
    }
    Ok(())
}

/// Writes the GIF.
pub fn run(args: &AnimateArgs) -> Result<Printed, BenchError> {
    if !(64..=4096).contains(&args.size) {
        return Err(usage("--size must be between 64 and 4096 pixels"));
    }
    if args.max_frames == 0 || args.delay_ms == 0 {
        return Err(usage("--max-frames and --delay-ms must be at least 1"));
    }
    let run = read_run(&args.file)?;
    if run.snapshots.is_empty() {
        // One frame is a still, not an animation: say how to record the run.
        return Err(usage(format!(
            "{} has no snapshots beside it (NAME_step<K>.txt), so its animation would be the final packing alone; record the run with `packbench pack ... --save-interval K --output NAME` and animate NAME.json",
            args.file.display()
        )));
    }
    let method = run
        .sidecar
        .as_ref()
        .map(|s| s.method.clone())
        .unwrap_or_else(|| run.name.clone());
    let mut frames: Vec<GifFrame<'_>> = thin(run.snapshots.iter().collect(), args.max_frames - 1)
        .into_iter()
        .map(|(step, p)| (format!("{method}, step {step}"), args.delay_ms, p))
        .collect();
    frames.push((format!("{method}, final"), 2000, &run.packing));
    let out = args
        .output
        .clone()
        .unwrap_or_else(|| args.file.with_extension("gif"));
    // Written beside the target and renamed: an interrupted run leaves no half GIF.
    let part = out.with_extension("gif.part");
    draw_gif(&part, args.size, args.delay_ms, &frames).map_err(|e| {
        let _ = std::fs::remove_file(&part);
        BenchError::Run(format!("drawing {}: {e}", out.display()))
    })?;
    std::fs::rename(&part, &out)
        .map_err(|e| BenchError::Run(format!("writing {}: {e}", out.display())))?;
    Ok(Printed {
        stdout: String::new(),
        stderr: vec![format!(
            "packbench animate: {} frames -> {}",
            frames.len(),
            out.display()
        )],
    })
}
