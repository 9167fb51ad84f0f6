//! The friction laws' own parameters as flags: one `--key` per key of any law
//! ([`FrictionLaw::keys`], an underscore written as a dash: `mu_0` is `--mu-0`), built with
//! clap's builder API from the laws themselves, with help from each key's long name and
//! default ([`Params::named`] of [`Params::defaults`]). A new law's keys become flags with no
//! edit here or in [`super::model`].

use clap::{Arg, ArgMatches, Args, Command, FromArgMatches};
use squeal_core::{FrictionLaw, Params};

/// Every law's keys, each once, in [`FrictionLaw::ALL`] order.
pub fn all_keys() -> Vec<&'static str> {
    let mut keys: Vec<&'static str> = Vec::new();
    for law in FrictionLaw::ALL {
        for k in law.keys() {
            if !keys.contains(k) {
                keys.push(k);
            }
        }
    }
    keys
}

/// The flag of `key`: `mu_0` is `--mu-0`.
pub fn flag(key: &str) -> String {
    format!("--{}", key.replace('_', "-"))
}

/// The help of `key`'s flag: its long name, then each default with the laws it is theirs
/// for, e.g. "belt speed v_d (--law stribeck: default 1.5; --law cubic: default 0.3)".
fn help(key: &str) -> String {
    let mut long_name = key;
    let mut defaults: Vec<(f64, Vec<&str>)> = Vec::new();
    for law in FrictionLaw::ALL {
        let named = Params::defaults(law).named();
        let Some(n) = named.into_iter().find(|n| n.name == key) else {
            continue;
        };
        long_name = n.long_name;
        match defaults.iter_mut().find(|(v, _)| *v == n.value) {
            Some((_, laws)) => laws.push(law.name()),
            None => defaults.push((n.value, vec![law.name()])),
        }
    }
    let each: Vec<String> = defaults
        .iter()
        .map(|(v, laws)| format!("--law {}: default {v}", laws.join(", ")))
        .collect();
    // Capitalised as clap's derive help of the other flags is.
    let mut chars = long_name.chars();
    let first = chars.next().map(|c| c.to_ascii_uppercase());
    format!(
        "{}{} ({})",
        first.unwrap_or(' '),
        chars.as_str(),
        each.join("; ")
    )
}

/// The values given to the law flags, by key, in [`all_keys`] order.
#[derive(Clone, Debug, Default)]
pub struct LawFlags(pub Vec<(&'static str, f64)>);

impl LawFlags {
    /// The value given for `key`, if any.
    pub fn get(&self, key: &str) -> Option<f64> {
        self.0.iter().find(|(k, _)| *k == key).map(|(_, v)| *v)
    }

    /// The first key given, if any.
    pub fn first(&self) -> Option<&'static str> {
        self.0.first().map(|(k, _)| *k)
    }
}

impl FromArgMatches for LawFlags {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let given = all_keys()
            .into_iter()
            .filter_map(|k| m.get_one::<f64>(k).map(|v| (k, *v)))
            .collect();
        Ok(LawFlags(given))
    }

    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = LawFlags::from_arg_matches(m)?;
        Ok(())
    }
}

impl Args for LawFlags {
    fn augment_args(cmd: Command) -> Command {
        all_keys().into_iter().fold(cmd, |cmd, k| {
            // clap keeps names as `&'static str`; a command is built once per run. The value
            // is named as clap's derive names it (`--v-d <V_D>`), as before.
            let long: &'static str = Box::leak(k.replace('_', "-").into_boxed_str());
            let value: &'static str = Box::leak(k.to_uppercase().into_boxed_str());
            cmd.arg(
                Arg::new(k)
                    .long(long)
                    .value_name(value)
                    .value_parser(clap::value_parser!(f64))
                    .allow_negative_numbers(true)
                    .help(help(k)),
            )
        })
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        LawFlags::augment_args(cmd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The flags users know (the hand-written ones these replace) are all still made.
    #[test]
    fn every_law_key_is_a_flag() {
        let want = [
            "nu", "lambda", "tau", "phi", "xi", "v_d", "mu_d", "mu_sd", "v_0", "mu_v", "mu_0",
            "a1", "a3",
        ];
        assert_eq!(all_keys(), want);
        assert_eq!(flag("mu_0"), "--mu-0");
        let cmd = LawFlags::augment_args(Command::new("t"));
        let m = cmd
            .try_get_matches_from(["t", "--mu-0", "0.3", "--v-d", "-1"])
            .unwrap();
        let f = LawFlags::from_arg_matches(&m).unwrap();
        assert_eq!(f.0, [("v_d", -1.0), ("mu_0", 0.3)]);
        assert_eq!(
            help("v_d"),
            // The laws' own defaults: Stribeck::V_D (bSTAB's, also the table law's) and
            // Cubic::V_D (crates/core/src/law/).
            "Belt speed v_d (--law stribeck, table: default 1.5; --law cubic: default 0.3)"
        );
    }
}
