//! The flags of `squeal critical` (their own file: the command, its report and its
//! lifetime table all read them).

use anyhow::bail;
use squeal_core::error::Number;
use squeal_scan::atlas::BoundaryParam;
use squeal_scan::section::ParamRange;

use super::model::SetupArgs;

/// Flags of `squeal critical`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub setup: SetupArgs,
    /// The state that must lie inside the cycle: x.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub x0: f64,
    /// ... and x'.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub v0: f64,
    /// Lower end of the bracket in nu (cycle must not enclose the state there).
    #[arg(long, default_value_t = 1e-3)]
    pub nu_lo: f64,
    /// Upper end (cycle must enclose the state there).
    #[arg(long, default_value_t = 5e-2)]
    pub nu_hi: f64,
    /// Relative width of the final bracket.
    #[arg(long, default_value_t = 1e-4)]
    pub rtol: f64,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Find the fold of cycles instead: the damping above which no start squeals.
    #[arg(long)]
    pub fold: bool,
    /// Find the crisis of the stick-slip band instead: the damping above which no start
    /// squeals for good (the band above the unstable cycle leaks), bisected at dt and
    /// dt/2, with an uncertainty that covers both (crates/core/MODEL.md, section 6).
    #[arg(long, conflicts_with = "fold")]
    pub crisis: bool,
    /// With --crisis or --fold (in nu): the mean transient lifetime of the leaking band (t_squeal of starts
    /// spread over the band) at nu_c (1 + f), f from 0.01 by factors 1.25 to 0.075, with its standard
    /// error, and its power law in nu - nu_c (crates/scan/src/lifetime.rs).
    #[arg(long)]
    pub lifetimes: bool,
    /// Starts on the band per damping (--lifetimes; 2 to 4096).
    #[arg(long, default_value_t = 128)]
    pub starts: usize,
    /// Runs still squealing at this time are censored (--lifetimes; nondimensional).
    #[arg(long, default_value_t = 40_000.0)]
    pub lifetime_t_max: f64,
    /// With --fold or --crisis of McMillan's laws: every verdict with the longer horizon
    /// (twice the band's samples and t_return), the computation whose crisis the stated
    /// uncertainty also covers (scripts/bench/fold-coverage.sh checks it).
    #[arg(long)]
    pub longer_horizon: bool,
    /// The parameter to bisect in: nu (the damping) or lambda (the belt speed); for the
    /// Stribeck law xi and v_d (nu and lambda are taken there too). The bracket flags keep
    /// the names --nu-lo ... --lambda-hi.
    #[arg(long = "in", default_value = "nu", value_parser = ["nu", "lambda", "xi", "v_d"])]
    pub in_: String,
    /// Lower end of the bracket in lambda (with --in lambda).
    #[arg(long, default_value_t = 0.5)]
    pub lambda_lo: f64,
    /// Upper end of the bracket in lambda (with --in lambda).
    #[arg(long, default_value_t = 6.0)]
    pub lambda_hi: f64,
}

impl Args {
    /// The band's budget of the crisis's verdicts at dt and dt/2.
    pub(super) fn budget(&self) -> squeal_scan::band::Budget {
        match self.longer_horizon {
            true => squeal_scan::band::Budget::Longer,
            false => squeal_scan::band::Budget::Standard,
        }
    }

    /// The bisection range in `param` from its flags (checked: 0 < lo < hi), and the flags'
    /// stem (`--nu-lo`, `--lambda-hi`, ...).
    pub(super) fn range(&self, param: BoundaryParam) -> anyhow::Result<(ParamRange, &'static str)> {
        let (lo, hi, flag) = match param {
            BoundaryParam::Nu => (self.nu_lo, self.nu_hi, "nu"),
            BoundaryParam::Lambda => (self.lambda_lo, self.lambda_hi, "lambda"),
        };
        if !(lo > 0.0 && hi > lo && hi.is_finite()) {
            let (lo, hi) = (Number(lo), Number(hi));
            bail!("--{flag}-lo {lo} / --{flag}-hi {hi}: expected 0 < lo < hi");
        }
        let rtol = self.rtol;
        Ok((ParamRange { lo, hi, rtol }, flag))
    }
}
