//! How many runs go at once: `--jobs` when given, else the CPUs a Slurm allocation gives each
//! task (`SLURM_CPUS_PER_TASK`), else every core. The flag is parsed in [`crate::args`]; this is
//! where it is resolved against the environment.

use crate::error::{BenchError, usage};

/// Runs at once for `compare`: `--jobs` when given, else the CPUs Slurm gave each task
/// (`SLURM_CPUS_PER_TASK`, set by `--cpus-per-task`), else 0, which rayon reads as every core.
///
/// Errors: a usage error when `SLURM_CPUS_PER_TASK` is set but not a positive integer.
pub fn jobs(flag: Option<usize>) -> Result<usize, BenchError> {
    jobs_from(flag, std::env::var("SLURM_CPUS_PER_TASK").ok().as_deref())
}

/// [`jobs`] with the environment variable's value passed in.
pub fn jobs_from(flag: Option<usize>, cpus_per_task: Option<&str>) -> Result<usize, BenchError> {
    if let Some(k) = flag {
        return Ok(k);
    }
    match cpus_per_task {
        None => Ok(0),
        Some(v) => match v.trim().parse::<usize>() {
            Ok(k) if k > 0 => Ok(k),
            _ => Err(usage(format!(
                "SLURM_CPUS_PER_TASK=`{v}` is not a CPU count; give --jobs instead"
            ))),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jobs_come_from_the_flag_then_the_allocation_then_every_core() {
        assert_eq!(jobs_from(Some(3), Some("8")).unwrap(), 3);
        assert_eq!(jobs_from(None, Some("4")).unwrap(), 4);
        assert_eq!(jobs_from(None, Some(" 2\n")).unwrap(), 2);
        assert_eq!(jobs_from(None, None).unwrap(), 0);
        for bad in ["0", "", "two", "-1", "2.5"] {
            let e = jobs_from(None, Some(bad)).unwrap_err();
            assert_eq!(e.exit_code(), 2, "{bad}");
            assert!(e.to_string().contains("SLURM_CPUS_PER_TASK"), "{e}");
        }
    }
}
