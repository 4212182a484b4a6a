//! Command-line flags shared by several subcommands, with RCPGenerator's names, and their
//! translation into the core's scene, container and distribution.

use std::path::PathBuf;

use clap::Args;
use packbench_core::scene::Placement;
use packbench_core::{Container, Scene, SizeDistribution};

use crate::error::{BenchError, usage};

/// The container: `--box`, `--walls`, `--fix-height`, and the shapes RCPGenerator lacks.
#[derive(Args, Clone, Debug, Default)]
pub struct ContainerArgs {
    /// Box lengths per axis, comma-separated (default: 1 on every axis).
    #[arg(long = "box", value_delimiter = ',', allow_hyphen_values = true)]
    pub box_lengths: Option<Vec<f64>>,
    /// Per axis 0 = periodic, 1 = hard wall; a negative first entry -t makes a (hyper)sphere of
    /// diameter box[0] over the first t axes (-2 circle/cylinder, -3 sphere, -4 4-ball).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub walls: Option<Vec<i64>>,
    /// Treat the last --box value as a multiple of the largest diameter and hold the height there.
    #[arg(long = "fix-height", alias = "fix_height")]
    pub fix_height: bool,
    /// A cylindrical shell over the first two axes: inner,outer radius (overrides the first two
    /// --box values; the other axes keep --box and --walls).
    #[arg(
        long,
        value_delimiter = ',',
        num_args = 1,
        conflicts_with = "hemispheres"
    )]
    pub shell: Option<Vec<f64>>,
    /// A walled brick (--box) minus two hemispheres of these radii centred on the faces normal to x.
    #[arg(long, value_delimiter = ',', num_args = 1)]
    pub hemispheres: Option<Vec<f64>>,
}

impl ContainerArgs {
    /// True when no container flag was given.
    pub fn is_empty(&self) -> bool {
        self.box_lengths.is_none()
            && self.walls.is_none()
            && self.shell.is_none()
            && self.hemispheres.is_none()
    }

    /// Refuses --walls that contradict --shell or --hemispheres: the shell walls its first two
    /// axes and the hemisphere-cut brick every axis, so a periodic or ball entry there would
    /// be silently dropped.
    fn check_walls_agree(&self, walls: &[i64]) -> Result<(), BenchError> {
        let given = || {
            walls
                .iter()
                .map(|w| w.to_string())
                .collect::<Vec<_>>()
                .join(",")
        };
        if self.shell.is_some() && walls.iter().take(2).any(|&w| w != 1) {
            return Err(usage(format!(
                "--shell makes a cylindrical shell walled over the first two axes, but --walls {} asks for {} there; give 1 on those axes (--walls sets only the axes after them) or leave --walls out",
                given(),
                if walls[0] < 0 {
                    "a ball"
                } else {
                    "a periodic axis"
                }
            )));
        }
        if self.hemispheres.is_some() && walls.iter().any(|&w| w != 1) {
            return Err(usage(format!(
                "--hemispheres makes a brick walled on every axis, but --walls {} asks for {}; give 1 on every axis or leave --walls out",
                given(),
                if walls[0] < 0 {
                    "a ball"
                } else {
                    "a periodic axis"
                }
            )));
        }
        Ok(())
    }

    /// The container in `dim` dimensions (`dim` fixes the default box when --box is absent).
    pub fn container(&self, dim: usize) -> Result<Container, BenchError> {
        let lengths = self.box_lengths.clone().unwrap_or_else(|| vec![1.0; dim]);
        if lengths.len() != dim {
            return Err(usage(format!(
                "--box has {} lengths but the packing is {dim}-dimensional; give one length per axis",
                lengths.len()
            )));
        }
        let walls = self.walls.clone().unwrap_or_default();
        self.check_walls_agree(&walls)?;
        let mut c = if let Some(r) = &self.shell {
            if r.len() != 2 {
                return Err(usage("--shell takes two radii: inner,outer"));
            }
            let flags: Vec<bool> = (2..dim)
                .map(|k| walls.get(k).is_some_and(|&w| w == 1))
                .collect();
            Container::cylindrical_shell(r[0], r[1], &lengths[2..], &flags)?
        } else if let Some(r) = &self.hemispheres {
            if r.len() != 2 {
                return Err(usage("--hemispheres takes two radii: R1,R2"));
            }
            Container::hemisphere_cut_brick(&lengths, [r[0], r[1]])?
        } else {
            Container::from_rcp_flags(&lengths, &walls)?
        };
        if self.fix_height {
            c.fix_height = Some(lengths[dim - 1]);
        }
        Ok(c)
    }
}

/// The size distribution, with `InitializeParticles`' flag names (all describe diameters).
#[derive(Args, Clone, Debug, Default)]
pub struct DistributionArgs {
    /// mono, bidisperse, gaussian, biGaussian, lognormal, lognormal-mean1, flat, powerlaw,
    /// exponential, weibull, gamma or custom.
    #[arg(long)]
    pub dist: Option<String>,
    /// Diameter (mono).
    #[arg(long = "d", alias = "D")]
    pub d: Option<f64>,
    /// First diameter (bidisperse).
    #[arg(long)]
    pub d1: Option<f64>,
    /// Second diameter (bidisperse).
    #[arg(long)]
    pub d2: Option<f64>,
    /// Number fraction of the first kind (bidisperse, biGaussian).
    #[arg(long)]
    pub p: Option<f64>,
    /// Mean (gaussian) or log-mean (lognormal).
    #[arg(long)]
    pub mu: Option<f64>,
    /// Std dev (gaussian), log-std (lognormal), or diameter std at mean 1 (lognormal-mean1).
    #[arg(long)]
    pub sigma: Option<f64>,
    /// Mean of the first Gaussian (biGaussian).
    #[arg(long)]
    pub mu1: Option<f64>,
    /// Std of the first Gaussian (biGaussian).
    #[arg(long)]
    pub sigma1: Option<f64>,
    /// Mean of the second Gaussian (biGaussian).
    #[arg(long)]
    pub mu2: Option<f64>,
    /// Std of the second Gaussian (biGaussian).
    #[arg(long)]
    pub sigma2: Option<f64>,
    /// Smallest diameter (flat, powerlaw, exponential).
    #[arg(long = "d_min", alias = "d-min")]
    pub d_min: Option<f64>,
    /// Largest diameter (flat, powerlaw, exponential).
    #[arg(long = "d_max", alias = "d-max")]
    pub d_max: Option<f64>,
    /// Exponent of the density D^a (powerlaw).
    #[arg(long, allow_hyphen_values = true)]
    pub exponent: Option<f64>,
    /// Scale (weibull λ, gamma θ).
    #[arg(long)]
    pub scale: Option<f64>,
    /// Shape (weibull k, gamma k).
    #[arg(long)]
    pub shape: Option<f64>,
    /// Comma-separated diameters (custom).
    #[arg(long = "custom_list", alias = "custom-list", value_delimiter = ',')]
    pub custom_list: Option<Vec<f64>>,
}

/// The field of one numeric distribution parameter ([`DistributionArgs::number_mut`]).
type NumberField = fn(&mut DistributionArgs) -> &mut Option<f64>;

impl DistributionArgs {
    /// The numeric parameters by the names the flags spell them (without dashes), each with
    /// its field: the one list [`Self::number_names`] and [`Self::number_mut`] read.
    const NUMBERS: [(&'static str, NumberField); 15] = [
        ("d", |a| &mut a.d),
        ("d1", |a| &mut a.d1),
        ("d2", |a| &mut a.d2),
        ("p", |a| &mut a.p),
        ("mu", |a| &mut a.mu),
        ("sigma", |a| &mut a.sigma),
        ("mu1", |a| &mut a.mu1),
        ("sigma1", |a| &mut a.sigma1),
        ("mu2", |a| &mut a.mu2),
        ("sigma2", |a| &mut a.sigma2),
        ("d_min", |a| &mut a.d_min),
        ("d_max", |a| &mut a.d_max),
        ("exponent", |a| &mut a.exponent),
        ("scale", |a| &mut a.scale),
        ("shape", |a| &mut a.shape),
    ];

    /// The names of the numeric parameters, as the flags spell them (without dashes).
    pub fn number_names() -> impl Iterator<Item = &'static str> {
        Self::NUMBERS.iter().map(|(name, _)| *name)
    }

    /// The numeric parameter named `name` (one of [`Self::number_names`]), for callers that
    /// set parameters by name (Python's keywords); `None` for another name.
    pub fn number_mut(&mut self, name: &str) -> Option<&mut Option<f64>> {
        let (_, field) = Self::NUMBERS.iter().find(|(n, _)| *n == name)?;
        Some(field(self))
    }

    /// The distribution the flags describe (mono d = 1 when no --dist is given).
    pub fn distribution(&self) -> Result<SizeDistribution, BenchError> {
        let name = self.dist.as_deref().unwrap_or("mono");
        let need = |v: Option<f64>, flag: &str| {
            v.ok_or_else(|| usage(format!("--dist {name} needs --{flag}")))
        };
        let dist = match name {
            "mono" | "monodisperse" => SizeDistribution::Mono {
                d: self.d.unwrap_or(1.0),
            },
            "bidisperse" => SizeDistribution::Bidisperse {
                d1: need(self.d1, "d1")?,
                d2: need(self.d2, "d2")?,
                p: need(self.p, "p")?,
            },
            "gaussian" => SizeDistribution::Gaussian {
                mu: need(self.mu, "mu")?,
                sigma: need(self.sigma, "sigma")?,
            },
            "biGaussian" | "bigaussian" => SizeDistribution::BiGaussian {
                mu1: need(self.mu1, "mu1")?,
                sigma1: need(self.sigma1, "sigma1")?,
                mu2: need(self.mu2, "mu2")?,
                sigma2: need(self.sigma2, "sigma2")?,
                p: need(self.p, "p")?,
            },
            "lognormal" => SizeDistribution::Lognormal {
                mu: need(self.mu, "mu")?,
                sigma: need(self.sigma, "sigma")?,
            },
            "lognormal-mean1" => SizeDistribution::LognormalMean1 {
                sigma: need(self.sigma, "sigma")?,
            },
            "flat" => SizeDistribution::Flat {
                d_min: need(self.d_min, "d_min")?,
                d_max: need(self.d_max, "d_max")?,
            },
            "powerlaw" => SizeDistribution::Powerlaw {
                d_min: need(self.d_min, "d_min")?,
                d_max: need(self.d_max, "d_max")?,
                exponent: need(self.exponent, "exponent")?,
            },
            "exponential" => SizeDistribution::Exponential {
                d_min: need(self.d_min, "d_min")?,
                d_max: need(self.d_max, "d_max")?,
            },
            "weibull" => SizeDistribution::Weibull {
                scale: need(self.scale, "scale")?,
                shape: need(self.shape, "shape")?,
            },
            "gamma" => SizeDistribution::Gamma {
                shape: need(self.shape, "shape")?,
                scale: need(self.scale, "scale")?,
            },
            "custom" => SizeDistribution::Custom {
                list: self
                    .custom_list
                    .clone()
                    .ok_or_else(|| usage("--dist custom needs --custom_list"))?,
            },
            other => {
                return Err(usage(format!(
                    "unknown distribution `{other}`; use mono, bidisperse, gaussian, biGaussian, lognormal, \
                     lognormal-mean1, flat, powerlaw, exponential, weibull, gamma or custom"
                )));
            }
        };
        dist.validate()?;
        Ok(dist)
    }
}

/// How a command that runs many packings runs them: `--jobs` and `--quiet`, the same in
/// `compare`, `sweep`, `reproduce` and `design`.
#[derive(Args, Clone, Debug, Default)]
pub struct BatchArgs {
    /// Runs at once (default: the CPUs of the Slurm task, SLURM_CPUS_PER_TASK, else all cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// No progress bar (nor the per-run log lines written when stderr is not a terminal).
    #[arg(long)]
    pub quiet: bool,
}

impl BatchArgs {
    /// Runs at once, 0 meaning every core ([`crate::allocation::jobs`]).
    pub fn jobs(&self) -> Result<usize, BenchError> {
        crate::allocation::jobs(self.jobs)
    }
}

/// Everything that makes a scene: `packbench init`'s flags, or `--scene FILE`.
#[derive(Args, Clone, Debug, Default)]
pub struct SceneArgs {
    /// A scene file (TOML or JSON); flags given as well override its values.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Number of particles.
    #[arg(long = "N", alias = "n")]
    pub n: Option<usize>,
    /// Dimension (≥ 2).
    #[arg(long = "Ndim", alias = "ndim")]
    pub ndim: Option<usize>,
    /// Initial packing fraction, 0 < phi < 1 (default 0.05).
    #[arg(long)]
    pub phi: Option<f64>,
    /// Centres: rsa (random sequential addition, no overlaps; default), random (whole spheres
    /// inside walls, overlapping) or poisson (centres anywhere inside, overlapping).
    #[arg(long)]
    pub placement: Option<String>,
    #[command(flatten)]
    pub distribution: DistributionArgs,
    #[command(flatten)]
    pub container: ContainerArgs,
}

/// The built-in default scene: 3D monodisperse, N = 1000, periodic unit box, φ = 0.05.
pub fn default_scene() -> Scene {
    Scene {
        n: 1000,
        distribution: SizeDistribution::Mono { d: 1.0 },
        container: Container::periodic_box(&[1.0, 1.0, 1.0]).expect("valid box"),
        phi: 0.05,
        seed: None,
        placement: Placement::Rsa,
    }
}

impl SceneArgs {
    /// The scene: the file (if any) or [`default_scene`], overridden by every flag given.
    pub fn scene(&self, seed: Option<u64>) -> Result<Scene, BenchError> {
        self.scene_or(default_scene(), seed)
    }

    /// The scene: the file (if any) or `default`, overridden by every flag given.
    pub fn scene_or(&self, default: Scene, seed: Option<u64>) -> Result<Scene, BenchError> {
        let mut scene = match &self.scene {
            Some(path) => Scene::read(path)?,
            None => default,
        };
        if let Some(n) = self.n {
            scene.n = n;
        }
        let dim = match (self.ndim, &self.container.box_lengths) {
            (Some(d), _) => d,
            (None, Some(b)) => b.len(),
            (None, None) => scene.dim(),
        };
        if dim < 2 {
            return Err(usage(format!(
                "--Ndim {dim}: packings need at least 2 dimensions"
            )));
        }
        if self.ndim.is_some() || !self.container.is_empty() || self.container.fix_height {
            scene.container = self.container.container(dim)?;
        }
        if self.distribution.dist.is_some() || self.distribution.d.is_some() {
            scene.distribution = self.distribution.distribution()?;
        }
        if let Some(phi) = self.phi {
            scene.phi = phi;
        }
        if let Some(pl) = &self.placement {
            scene.placement = match pl.as_str() {
                "rsa" => Placement::Rsa,
                "random" => Placement::Random,
                "poisson" => Placement::Poisson,
                other => {
                    return Err(usage(format!(
                        "unknown placement `{other}`; use rsa, random or poisson"
                    )));
                }
            };
        }
        if seed.is_some() {
            scene.seed = seed;
        }
        scene.validate()?;
        Ok(scene)
    }
}

/// The default comparison: 2D bidisperse disks (diameters 1 and 1.4, equal numbers, the
/// classic glass-former), N = 40 in a periodic box, so that every method — including the slow
/// exact ones — finishes in about a minute on 2 cores, and the packings can be drawn to scale.
pub fn default_compare_scene() -> Scene {
    let mut s = default_scene();
    s.n = 40;
    s.distribution = packbench_core::SizeDistribution::Bidisperse {
        d1: 1.0,
        d2: 1.4,
        p: 0.5,
    };
    s.container = packbench_core::Container::periodic_box(&[1.0, 1.0]).expect("valid box");
    s
}
