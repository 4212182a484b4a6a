//! A run's parameters resolved from their sources in one order, so that `pack`, `compare`,
//! `sweep`, `reproduce`, `design` and the Python module give a method the same parameter object
//! for the same request.
//!
//! The sources, each overriding the ones before it:
//! 1. the method's defaults ([`Method::default_params`]), or the parameters a resumed run
//!    began with ([`ParamSources::resolve_over`]);
//! 2. what the method derives from the scene flags ([`Method::scene_overrides`]: seq-fill
//!    fills a brick with the `--dist` sizes);
//! 3. `--set KEY=VALUE` (`--set METHOD.KEY=VALUE` picked for the method, [`set_for`];
//!    Python's parameter keywords; the value a sweep varies);
//! 4. the method's own options (`pack`'s method flags, [`super::flags::overrides`]; Python's
//!    named keywords such as `contact_tol`);
//! 5. the step budget ([`Method::budget_key`]) and the snapshot interval
//!    ([`Method::snapshot_key`]);
//! 6. the seed ([`Method::seed_key`]), for the methods that draw random numbers.
//!
//! A key the method does not have, a `--set` that does not parse and a budget or snapshot
//! interval for a method that takes none are usage errors.

use serde_json::{Map, Value};

use super::Method;
use crate::args::SceneArgs;
use crate::error::{BenchError, usage};

/// The sources of one run's parameters beside the method's defaults, in the order of the
/// module's list; each left empty adds nothing.
#[derive(Clone, Debug, Default)]
pub struct ParamSources<'a> {
    /// The scene flags the method may derive parameters from (`pack`'s).
    pub scene: Option<&'a SceneArgs>,
    /// `--set KEY=VALUE` overrides, in the order given.
    pub set: Vec<(String, Value)>,
    /// The method's own options as parameter overrides.
    pub options: Vec<(String, Value)>,
    /// The step budget, in the method's own unit.
    pub max_steps: Option<u64>,
    /// The snapshot interval, in the method's steps.
    pub save_interval: Option<u64>,
    /// The seed of the run's random choices; ignored by a method that draws none.
    pub seed: Option<u64>,
}

impl ParamSources<'_> {
    /// The complete parameter object of `method` for these sources, over its defaults.
    pub fn resolve(&self, method: &dyn Method) -> Result<Map<String, Value>, BenchError> {
        self.resolve_over(method, method.default_params())
    }

    /// The complete parameter object of `method` for these sources, over `base` (a complete
    /// parameter object: a checkpoint's own, for `pack --resume`).
    pub fn resolve_over(
        &self,
        method: &dyn Method,
        base: Map<String, Value>,
    ) -> Result<Map<String, Value>, BenchError> {
        let given: Vec<(String, Value)> = self.set.iter().chain(&self.options).cloned().collect();
        let mut overrides = match self.scene {
            Some(scene) => method.scene_overrides(scene, &given)?,
            None => Vec::new(),
        };
        overrides.extend(given);
        if let Some(steps) = self.max_steps {
            let key = method
                .budget_key()
                .ok_or_else(|| usage(format!("method {} takes no step budget", method.name())))?;
            overrides.push((key.to_string(), Value::from(steps)));
        }
        if let Some(every) = self.save_interval {
            let key = method
                .snapshot_key()
                .ok_or_else(|| usage(format!("method {} passes no snapshots", method.name())))?;
            overrides.push((key.to_string(), Value::from(every)));
        }
        if let (Some(seed), Some(key)) = (self.seed, method.seed_key()) {
            overrides.push((key.to_string(), Value::from(seed)));
        }
        apply_overrides(method, base, &overrides)
    }
}

/// `params` (a complete parameter object of `method`) with `overrides` applied in order; an
/// unknown key is a usage error.
fn apply_overrides(
    method: &dyn Method,
    mut params: Map<String, Value>,
    overrides: &[(String, Value)],
) -> Result<Map<String, Value>, BenchError> {
    for (key, value) in overrides {
        match slot(&mut params, key) {
            Some(slot) => *slot = value.clone(),
            None => {
                let known: Vec<_> = params.keys().cloned().collect();
                return Err(usage(format!(
                    "method {} has no parameter `{key}`; its parameters are {}",
                    method.name(),
                    known.join(", ")
                )));
            }
        }
    }
    Ok(params)
}

/// The parameter at a dotted path (`dynamics.pressure_cap`).
fn slot<'a>(params: &'a mut Map<String, Value>, key: &str) -> Option<&'a mut Value> {
    let mut parts = key.split('.');
    let mut v = params.get_mut(parts.next()?)?;
    for part in parts {
        v = v.as_object_mut()?.get_mut(part)?;
    }
    Some(v)
}

/// Parses `key=value`; the value is read as JSON when it parses (numbers, booleans, strings in
/// quotes) and as a plain string otherwise.
pub fn parse_override(s: &str) -> Result<(String, Value), BenchError> {
    let (k, v) = s
        .split_once('=')
        .ok_or_else(|| usage(format!("--set `{s}` must look like key=value")))?;
    let value = serde_json::from_str(v).unwrap_or_else(|_| Value::String(v.to_string()));
    Ok((k.trim().to_string(), value))
}

/// The `--set KEY=VALUE` flags of one method's run, parsed.
pub fn parse_overrides(set: &[String]) -> Result<Vec<(String, Value)>, BenchError> {
    set.iter().map(|s| parse_override(s)).collect()
}

/// The `--set METHOD.KEY=VALUE` flags of several methods' runs as `(method, key, value)`.
///
/// Errors: a usage error for a flag that does not parse or names no method.
pub fn method_overrides(set: &[String]) -> Result<Vec<(String, String, Value)>, BenchError> {
    let mut overrides = Vec::new();
    for s in set {
        let (key, value) = parse_override(s)?;
        let (m, k) = key.split_once('.').ok_or_else(|| {
            usage(format!(
                "--set `{s}` must name its method: METHOD.KEY=VALUE"
            ))
        })?;
        overrides.push((m.to_string(), k.to_string(), value));
    }
    Ok(overrides)
}

/// The `(key, value)` overrides of `method` among `(method, key, value)` ones.
pub fn set_for(overrides: &[(String, String, Value)], method: &str) -> Vec<(String, Value)> {
    overrides
        .iter()
        .filter(|(m, _, _)| m == method)
        .map(|(_, k, v)| (k.clone(), v.clone()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::find;

    fn pair(key: &str, value: impl Into<Value>) -> (String, Value) {
        (key.to_string(), value.into())
    }

    /// Each source overrides the ones before it: defaults, scene, `--set`, options, budget,
    /// seed.
    #[test]
    fn a_later_source_overrides_an_earlier_one() {
        let ls = find("ls").unwrap();
        let set = vec![
            pair("rate", 0.5),
            pair("max_collisions", 7),
            pair("seed", 3),
        ];
        let set_only = ParamSources {
            set: set.clone(),
            ..Default::default()
        }
        .resolve(ls)
        .unwrap();
        assert_eq!(set_only["rate"], 0.5);
        assert_eq!(set_only["max_collisions"], 7);
        assert_eq!(set_only["seed"], 3);
        let all = ParamSources {
            set,
            options: vec![pair("rate", 0.25)],
            max_steps: Some(9),
            seed: Some(4),
            ..Default::default()
        }
        .resolve(ls)
        .unwrap();
        assert_eq!(all["rate"], 0.25);
        assert_eq!(all["max_collisions"], 9);
        assert_eq!(all["seed"], 4);
        // Untouched keys keep their defaults.
        assert_eq!(all["pressure_cap"], ls.default_params()["pressure_cap"]);
    }

    /// The scene's derived parameters come before `--set`, which overrides them.
    #[test]
    fn set_overrides_what_the_scene_derives() {
        let seq_fill = find("seq-fill").unwrap();
        let mut scene = SceneArgs::default();
        scene.distribution.dist = Some("mono".into());
        let derived = ParamSources {
            scene: Some(&scene),
            ..Default::default()
        };
        assert_eq!(derived.resolve(seq_fill).unwrap()["from_start"], false);
        let overridden = ParamSources {
            set: vec![pair("from_start", true)],
            ..derived
        };
        assert_eq!(overridden.resolve(seq_fill).unwrap()["from_start"], true);
    }

    #[test]
    fn unknown_keys_and_budgets_a_method_lacks_are_usage_errors() {
        let adam = find("adam").unwrap();
        let unknown = ParamSources {
            options: vec![pair("nope", 1)],
            ..Default::default()
        };
        let e = unknown.resolve(adam).unwrap_err();
        assert!(matches!(&e, BenchError::Usage(m) if m.contains("has no parameter `nope`")));
        let budget = ParamSources {
            max_steps: Some(5),
            ..Default::default()
        };
        let e = budget.resolve(find("seq-fill").unwrap()).unwrap_err();
        assert!(matches!(&e, BenchError::Usage(m) if m.contains("takes no step budget")));
        // A seed is ignored by a method that draws no random numbers.
        let seeded = ParamSources {
            seed: Some(5),
            ..Default::default()
        };
        assert_eq!(seeded.resolve(adam).unwrap(), adam.default_params());
    }

    #[test]
    fn set_flags_name_their_method() {
        let o = method_overrides(&["mls.rate_final=1e-12".into()]).unwrap();
        assert_eq!(set_for(&o, "mls"), [pair("rate_final", 1e-12)]);
        assert!(set_for(&o, "ls").is_empty());
        let e = method_overrides(&["rate_final=1e-12".into()]).unwrap_err();
        assert!(matches!(&e, BenchError::Usage(m) if m.contains("must name its method")));
    }
}
