//! A scene: what a user asks for — dimension, particle count, size distribution, container,
//! initial packing fraction and seed. Serialisable as TOML or JSON.

use serde::{Deserialize, Serialize};

use crate::container::Container;
use crate::distribution::SizeDistribution;
use crate::error::CoreError;

/// How initial centres are placed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Placement {
    /// Random sequential addition (RCPGenerator's `InitializeParticles`): centres drawn
    /// uniformly, each whole sphere inside its walls, and a draw kept only when the sphere
    /// overlaps none placed before it, largest first. It saturates below random close packing
    /// (equal spheres near φ ≈ 0.38 in 3D, disks near 0.55 in 2D); above the φ it reaches the
    /// placement is an error.
    #[default]
    Rsa,
    /// Uniformly random centres inside the container, each whole sphere inside its walls,
    /// overlapping each other freely (the default before random sequential addition).
    Random,
    /// A Poisson configuration: uniformly random centres, diameters kept as sampled but the
    /// packing starts at φ = 0 by scaling them to zero (Lubachevsky–Stillinger's start).
    /// The stored diameters are the sampled ones scaled so φ = `phi`; methods that grow
    /// from zero use only their ratios. The spheres overlap each other and may cross walls.
    Poisson,
}

/// What a user asks for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    /// Number of particles.
    pub n: usize,
    /// Size distribution of diameters.
    #[serde(flatten)]
    pub distribution: SizeDistribution,
    /// The container; its dimension is the scene's.
    pub container: Container,
    /// Initial packing fraction (0 < φ < 1).
    #[serde(default = "default_phi")]
    pub phi: f64,
    /// Seed of every random choice; `None` means time-based (printed by the binary).
    #[serde(default)]
    pub seed: Option<u64>,
    /// Placement of the initial centres.
    #[serde(default)]
    pub placement: Placement,
}

fn default_phi() -> f64 {
    0.05
}

impl Scene {
    /// RCPGenerator 1.0's walled benchmark: `n` spheres of
    /// [`SizeDistribution::power_law_1_to_15`] at `phi`, random (overlapping) centres in a
    /// 1 × 0.5 × 1 box with walls on y, periodic along x and z.
    pub fn power_law_between_walls(n: usize, phi: f64, seed: u64) -> Scene {
        Scene {
            n,
            distribution: SizeDistribution::power_law_1_to_15(),
            container: Container::with_flags(&[1.0, 0.5, 1.0], &[false, true, false])
                .expect("a valid box"),
            phi,
            seed: Some(seed),
            placement: Placement::Random,
        }
    }

    /// Dimension.
    pub fn dim(&self) -> usize {
        self.container.dim()
    }

    /// Checks ranges.
    pub fn validate(&self) -> Result<(), CoreError> {
        self.container.validate()?;
        self.distribution.validate()?;
        if !(self.phi > 0.0 && self.phi < 1.0) {
            return Err(CoreError::Parameter(format!(
                "initial packing fraction phi = {} must lie strictly between 0 and 1",
                self.phi
            )));
        }
        if self.n == 0 {
            return Err(CoreError::Parameter(
                "a scene needs at least one particle (N ≥ 1)".into(),
            ));
        }
        Ok(())
    }

    /// Parses a scene from TOML or JSON text; `name` is used in error messages and its
    /// extension picks the format (`.json` → JSON, anything else → TOML).
    pub fn parse(name: &str, text: &str) -> Result<Scene, CoreError> {
        let scene: Scene = if name.ends_with(".json") {
            serde_json::from_str(text).map_err(|e| CoreError::Parse {
                file: name.into(),
                line: e.line(),
                column: e.column(),
                message: e.to_string(),
            })?
        } else {
            toml::from_str(text).map_err(|e| {
                let (line, column) = e.span().map(|s| line_col(text, s.start)).unwrap_or((1, 1));
                CoreError::Parse {
                    file: name.into(),
                    line,
                    column,
                    message: e.message().to_string(),
                }
            })?
        };
        scene.validate()?;
        Ok(scene)
    }

    /// Reads a scene file (TOML or JSON by extension). A file that cannot be read is bad input
    /// ([`CoreError::File`]), like one that does not parse.
    pub fn read(path: &std::path::Path) -> Result<Scene, CoreError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| CoreError::File {
            file: name.clone(),
            message: format!("cannot read the scene file: {e}"),
        })?;
        Scene::parse(&name, &text)
    }

    /// The scene as TOML.
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).expect("scenes always serialise")
    }
}

/// 1-based line and column of a byte offset.
pub(crate) fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before
        .rfind('\n')
        .map_or(before.len(), |p| before.len() - p - 1)
        + 1;
    (line, column)
}
