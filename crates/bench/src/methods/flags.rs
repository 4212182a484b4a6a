//! Method flags: each method declares the options of `packbench pack` that set one of its
//! parameters, beside its parameters, and `pack` gathers them from the registry. Adding a
//! method or a flag touches the method's file only.

use clap::{Arg, ArgAction, ArgMatches, Command};
use serde_json::Value;

use crate::error::{BenchError, usage};

/// What a flag's value is, and how it is parsed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlagValue {
    /// A real number.
    Number,
    /// A non-negative whole number.
    Count,
    /// A word (a protocol name, …).
    Text,
    /// Comma-separated real numbers.
    Numbers,
    /// Comma-separated non-negative whole numbers.
    Counts,
    /// Present or absent: sets the parameter to `true`.
    Switch,
    /// Present or absent: runs the named variant of the method instead (`--qp` runs
    /// closest-jammed as closest-jammed-qp).
    RunsVariant(&'static str),
}

/// One option of `packbench pack` that a method takes.
#[derive(Clone, Copy, Debug)]
pub struct MethodFlag {
    /// The long name, without dashes (`rate` for `--rate`).
    pub name: &'static str,
    /// The parameter it sets (a key of the method's parameter object).
    pub key: &'static str,
    /// One line of help.
    pub help: &'static str,
    /// Its value.
    pub value: FlagValue,
}

impl MethodFlag {
    /// A flag taking a real number.
    pub const fn number(name: &'static str, key: &'static str, help: &'static str) -> Self {
        MethodFlag {
            name,
            key,
            help,
            value: FlagValue::Number,
        }
    }

    /// A flag of another kind.
    pub const fn new(
        name: &'static str,
        key: &'static str,
        value: FlagValue,
        help: &'static str,
    ) -> Self {
        MethodFlag {
            name,
            key,
            help,
            value,
        }
    }
}

/// A flag as `pack` offers it: one `--name` for every method that declares it.
struct Offered {
    flag: MethodFlag,
    methods: Vec<&'static str>,
}

/// Every method flag of the registry, each name once, in registry order.
fn offered(methods: &[&'static dyn super::Method]) -> Vec<Offered> {
    let mut out: Vec<Offered> = Vec::new();
    for m in methods {
        for f in m.flags() {
            match out.iter_mut().find(|o| o.flag.name == f.name) {
                Some(o) => o.methods.push(m.name()),
                None => out.push(Offered {
                    flag: *f,
                    methods: vec![m.name()],
                }),
            }
        }
    }
    out
}

/// `command` with every method flag of the registry added, under a heading naming the
/// methods that take it, and the methods' notes after its help.
pub fn add_to(command: Command) -> Command {
    let command = command.after_help(super::pack_help_notes());
    offered(&super::registry())
        .into_iter()
        .fold(command, |c, o| {
            let arg = Arg::new(o.flag.name)
                .long(o.flag.name)
                .help(o.flag.help)
                .help_heading(o.methods.join(" / "));
            let arg = match o.flag.value {
                FlagValue::Switch | FlagValue::RunsVariant(_) => arg.action(ArgAction::SetTrue),
                FlagValue::Numbers | FlagValue::Counts => arg
                    .value_delimiter(',')
                    .num_args(1..)
                    .allow_negative_numbers(true),
                _ => arg.allow_negative_numbers(true),
            };
            c.arg(arg)
        })
}

/// The method flags given on a command line: `(name, value)` pairs, values as the text the
/// user typed (lists comma-joined), in registry order.
pub fn given(matches: &ArgMatches) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for o in offered(&super::registry()) {
        let name = o.flag.name;
        match o.flag.value {
            FlagValue::Switch | FlagValue::RunsVariant(_) => {
                if matches.get_flag(name) {
                    out.push((name.to_string(), "true".to_string()));
                }
            }
            _ => {
                if let Some(v) = matches.get_many::<String>(name) {
                    out.push((name.to_string(), v.cloned().collect::<Vec<_>>().join(",")));
                }
            }
        }
    }
    out
}

/// The method to run: `name`, or the variant a given switch selects (`--qp`).
pub fn method_name(name: &str, given: &[(String, String)]) -> Result<String, BenchError> {
    let registry = super::registry();
    for (flag, _) in given {
        let variant = registry
            .iter()
            .flat_map(|m| m.flags().iter().map(move |f| (m.name(), f)))
            .find(|(_, f)| f.name == flag.as_str());
        if let Some((owner, f)) = variant
            && let FlagValue::RunsVariant(v) = f.value
        {
            return if name == owner || name == v {
                Ok(v.to_string())
            } else {
                Err(usage(format!("--{flag} applies to {owner}, not to {name}")))
            };
        }
    }
    Ok(name.to_string())
}

/// Parameter overrides from the method flags `given` for `method`; a flag the method does not
/// take, or a value of the wrong kind, is a usage error that names the flag.
pub fn overrides(
    method: &dyn super::Method,
    given: &[(String, String)],
) -> Result<Vec<(String, Value)>, BenchError> {
    let mut out = Vec::new();
    let registry = super::registry();
    let selects_variant = |name: &str| {
        registry
            .iter()
            .flat_map(|m| m.flags())
            .any(|f| f.name == name && matches!(f.value, FlagValue::RunsVariant(_)))
    };
    for (name, text) in given {
        if selects_variant(name) {
            // Already resolved by `method_name`.
            continue;
        }
        let Some(f) = method.flags().iter().find(|f| f.name == name.as_str()) else {
            return Err(usage(format!(
                "--{name} does not apply to method {}",
                method.name()
            )));
        };
        out.push((f.key.to_string(), parse(f, text)?));
    }
    Ok(out)
}

/// The JSON value of `text` given to flag `f`.
fn parse(f: &MethodFlag, text: &str) -> Result<Value, BenchError> {
    let bad = |what: &str| usage(format!("--{} takes {what}, not `{text}`", f.name));
    let number = |s: &str| {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .map(Value::from)
            .ok_or_else(|| bad("a finite number"))
    };
    let count = |s: &str| {
        s.trim()
            .parse::<u64>()
            .map(Value::from)
            .map_err(|_| bad("a whole number"))
    };
    let list = |item: &dyn Fn(&str) -> Result<Value, BenchError>| {
        text.split(',')
            .map(item)
            .collect::<Result<Vec<_>, _>>()
            .map(Value::from)
    };
    match f.value {
        FlagValue::Number => number(text),
        FlagValue::Count => count(text),
        FlagValue::Text => Ok(Value::from(text)),
        FlagValue::Numbers => list(&number),
        FlagValue::Counts => list(&count),
        FlagValue::Switch | FlagValue::RunsVariant(_) => Ok(Value::Bool(true)),
    }
}
