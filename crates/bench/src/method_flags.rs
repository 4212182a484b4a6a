//! The method options the issues name as flags of `packbench pack`, each mapped onto a
//! parameter of the method's `Params` (everything else is reachable with `--set KEY=VALUE`).

use clap::Args;
use serde_json::Value;

use crate::args::SceneArgs;
use crate::error::{BenchError, usage};
use crate::methods::Method;

/// Method options of `packbench pack`.
#[derive(Args, Debug, Default)]
pub struct MethodFlags {
    /// adam/fire: grow to this φ and stop overlap-free (below jamming; DEM initial conditions).
    #[arg(long = "target-phi", help_heading = "adam / fire")]
    pub target_phi: Option<f64>,
    /// adam/fire: threshold (seed 000's inflate/deflate loop) or pressure (diameter scale minimised
    /// against a pressure term lowered in rungs).
    #[arg(long, help_heading = "adam / fire")]
    pub protocol: Option<String>,
    /// adam/fire: final Δφ step tolerance (termination).
    #[arg(long = "delta-phi-tol", help_heading = "adam / fire")]
    pub delta_phi_tol: Option<f64>,
    /// fire: largest FIRE time step.
    #[arg(long = "dt-max", help_heading = "adam / fire")]
    pub dt_max: Option<f64>,
    /// ls: compression rate γ (diameter growth relative to the mean diameter per unit time).
    #[arg(long, help_heading = "ls / mls")]
    pub rate: Option<f64>,
    /// ls/mls: reduced pressure at which compression stops or γ is divided (default 1e12).
    #[arg(long = "pressure-cap", help_heading = "ls / mls")]
    pub pressure_cap: Option<f64>,
    /// mls: initial γ (default 10).
    #[arg(long = "rate-initial", help_heading = "ls / mls")]
    pub rate_initial: Option<f64>,
    /// mls: factor γ is divided by at each pressure cap (default 2).
    #[arg(long = "rate-factor", help_heading = "ls / mls")]
    pub rate_factor: Option<f64>,
    /// mls: stop when γ falls below this (default 1e-4).
    #[arg(long = "rate-final", help_heading = "ls / mls")]
    pub rate_final: Option<f64>,
    /// closest-jammed: use the QP form (bonds may open), one clarabel QP per step; same as
    /// --method closest-jammed-qp.
    #[arg(long, help_heading = "closest-jammed / calippso")]
    pub qp: bool,
    /// closest-jammed: the QP form's steepest descent solved as an active set on the sparse
    /// factor: every bond whose force turns tensile opens (tens of times fewer steps than --qp).
    #[arg(
        long = "open-tensile-bonds",
        help_heading = "closest-jammed / calippso"
    )]
    pub open_tensile_bonds: bool,
    /// calippso: tolerance on √Γ − 1.
    #[arg(long = "tol-gamma", help_heading = "closest-jammed / calippso")]
    pub tol_gamma: Option<f64>,
    /// calippso: tolerance on the largest non-rattler displacement.
    #[arg(long = "tol-s", help_heading = "closest-jammed / calippso")]
    pub tol_s: Option<f64>,
    /// calippso: largest overlap tolerated in the overlap checks.
    #[arg(long = "tol-overlap", help_heading = "closest-jammed / calippso")]
    pub tol_overlap: Option<f64>,
    /// seq-fill: 1 (reflected bricks) or 2 (copied bricks).
    #[arg(long, help_heading = "seq-fill")]
    pub variant: Option<u8>,
    /// seq-fill: unit brick side lengths, absolute (then the fill uses the --dist flags, not a start).
    #[arg(long, value_delimiter = ',', help_heading = "seq-fill")]
    pub brick: Option<Vec<f64>>,
    /// seq-fill: bricks per axis.
    #[arg(long, value_delimiter = ',', help_heading = "seq-fill")]
    pub bricks: Option<Vec<usize>>,
    /// seq-fill: FaceGoal, the face fraction to reach.
    #[arg(long = "face-goal", help_heading = "seq-fill")]
    pub face_goal: Option<f64>,
    /// seq-fill: BodyGoal, the volume fraction to reach.
    #[arg(long = "body-goal", help_heading = "seq-fill")]
    pub body_goal: Option<f64>,
    /// seq-fill: SphereContactParameter ε (contacts within ε·r̄).
    #[arg(long = "contact-param", help_heading = "seq-fill")]
    pub contact_param: Option<f64>,
    /// seq-fill: ParentParameter δ (parents within δ·r̄).
    #[arg(long = "parent-param", help_heading = "seq-fill")]
    pub parent_param: Option<f64>,
}

impl MethodFlags {
    /// The method actually run (`--qp` turns closest-jammed into closest-jammed-qp).
    pub fn method_name<'a>(&self, name: &'a str) -> Result<&'a str, BenchError> {
        match (self.qp, name) {
            (false, n) => Ok(n),
            (true, "closest-jammed" | "closest-jammed-qp") => Ok("closest-jammed-qp"),
            (true, n) => Err(usage(format!("--qp applies to closest-jammed, not to {n}"))),
        }
    }

    /// Parameter overrides for `method`; a flag the method does not take is a usage error.
    pub fn overrides(
        &self,
        method: &dyn Method,
        scene: &SceneArgs,
    ) -> Result<Vec<(String, Value)>, BenchError> {
        let defaults = method.default_params();
        let mut out = Vec::new();
        let mut set = |flag: &str, key: &str, v: Option<Value>| -> Result<(), BenchError> {
            if let Some(v) = v {
                if !defaults.contains_key(key) {
                    return Err(usage(format!(
                        "--{flag} does not apply to method {}",
                        method.name()
                    )));
                }
                out.push((key.to_string(), v));
            }
            Ok(())
        };
        let num = |v: Option<f64>| v.map(Value::from);
        set("target-phi", "target_phi", num(self.target_phi))?;
        set(
            "protocol",
            "protocol",
            self.protocol.clone().map(Value::from),
        )?;
        set("delta-phi-tol", "delta_phi_tol", num(self.delta_phi_tol))?;
        set("dt-max", "fire_dt_max", num(self.dt_max))?;
        set("rate", "rate", num(self.rate))?;
        set("pressure-cap", "pressure_cap", num(self.pressure_cap))?;
        set("rate-initial", "rate_initial", num(self.rate_initial))?;
        set("rate-factor", "rate_factor", num(self.rate_factor))?;
        set("rate-final", "rate_final", num(self.rate_final))?;
        set(
            "open-tensile-bonds",
            "open_tensile_bonds",
            self.open_tensile_bonds.then_some(Value::from(true)),
        )?;
        set("tol-gamma", "tol_gamma", num(self.tol_gamma))?;
        set("tol-s", "tol_s", num(self.tol_s))?;
        set("tol-overlap", "tol_overlap", num(self.tol_overlap))?;
        set("variant", "variant", self.variant.map(Value::from))?;
        set(
            "brick",
            "brick_lengths",
            self.brick.clone().map(Value::from),
        )?;
        set(
            "bricks",
            "brick_numbers",
            self.bricks.clone().map(Value::from),
        )?;
        set("face-goal", "face_goal", num(self.face_goal))?;
        set("body-goal", "body_goal", num(self.body_goal))?;
        set("contact-param", "contact_param", num(self.contact_param))?;
        set("parent-param", "parent_param", num(self.parent_param))?;
        if defaults.contains_key("from_start") {
            // seq-fill builds its own bed: with a brick or a distribution given it fills that
            // brick with that distribution instead of mirroring a starting packing.
            if self.brick.is_some() || scene.distribution.dist.is_some() {
                out.push(("from_start".into(), Value::Bool(false)));
                if scene.distribution.dist.is_some() {
                    let dist = scene.distribution.distribution()?;
                    out.push((
                        "distribution".into(),
                        serde_json::to_value(dist).map_err(|e| BenchError::Run(e.to_string()))?,
                    ));
                }
            }
            if let Some(h) = &scene.container.hemispheres {
                out.push(("hemispheres".into(), Value::from(h.clone())));
            }
        }
        Ok(out)
    }
}
