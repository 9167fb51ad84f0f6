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
    #[arg(long, default_value_t = BoundaryParam::Nu.default_bracket().0)]
    pub nu_lo: f64,
    /// Upper end (cycle must enclose the state there) [default: 0.05; where the answer
    /// comes from runs, raised by 4 up to 4 while a start still squeals there].
    #[arg(long)]
    pub nu_hi: Option<f64>,
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
    #[arg(long, default_value_t = BoundaryParam::Lambda.default_bracket().0)]
    pub lambda_lo: f64,
    /// Upper end of the bracket in lambda (with --in lambda) [default: 6; where the answer
    /// comes from runs, raised by 4 up to 96 while a start still squeals there].
    #[arg(long)]
    pub lambda_hi: Option<f64>,
    /// The horizon of the runs that confirm an answer or, outside the region the shortcuts
    /// were checked in, give it (nondimensional time; the unforced period is 2 pi): a run
    /// still oscillating there lasts, one at the fixed point settles.
    #[arg(long, default_value_t = squeal_scan::fates::HORIZON)]
    pub horizon: f64,
}

impl Args {
    /// Whether the top of the bracket in `param` was given by its flag.
    pub(super) fn top_given(&self, param: BoundaryParam) -> bool {
        match param {
            BoundaryParam::Nu => self.nu_hi.is_some(),
            BoundaryParam::Lambda => self.lambda_hi.is_some(),
        }
    }

    /// The ceiling of the runs' search in `param` over `range`, by the library's rule
    /// ([`BoundaryParam::ceiling`]).
    pub(super) fn ceiling(&self, param: BoundaryParam, range: ParamRange) -> f64 {
        param.ceiling(range, self.top_given(param))
    }

    /// The gate ([`squeal_scan::fates::decide`]) with these flags: the range in `param`
    /// and its ceiling, the horizon; `shortcut` as the gate takes it.
    pub(super) fn decide<T>(
        &self,
        (setup, param): (squeal_core::Setup, BoundaryParam),
        starts: &[squeal_core::State],
        range: ParamRange,
        shortcut: impl FnOnce() -> Result<(T, Option<[f64; 2]>), squeal_scan::ScanError>,
    ) -> Result<squeal_scan::fates::Decided<T>, squeal_scan::ScanError> {
        let ranges = (range, self.ceiling(param, range));
        squeal_scan::fates::decide((setup, param), starts, ranges, self.horizon, shortcut)
    }

    /// The horizon, checked: finite, positive, and at most `MAX_STEPS` steps of `dt`.
    pub(super) fn check_horizon(&self, dt: f64) -> anyhow::Result<()> {
        let inv = super::physical::start_invalid("command line".into(), None);
        squeal_scan::bounds::horizon("--horizon", self.horizon, dt, &inv)?;
        Ok(())
    }

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
        let hi = hi.unwrap_or(param.default_bracket().1);
        if !(lo > 0.0 && hi > lo && hi.is_finite()) {
            let (lo, hi) = (Number(lo), Number(hi));
            bail!("--{flag}-lo {lo} / --{flag}-hi {hi}: expected 0 < lo < hi");
        }
        let rtol = self.rtol;
        Ok((ParamRange { lo, hi, rtol }, flag))
    }
}
