//! The audit that acts: a rule an audited cell refutes is withdrawn from its map,
//! and every cell it decided there is decided again without it, before the file is written.
//!
//! The audit ([`crate::cell::Audit`]) runs a sample of a map's cells to settlement beside
//! their early decision ([`crate::scanner::AuditRates`]: about
//! [`crate::scanner::AUDIT_PER_RULE`] cells of each group of the start rule, and as many of
//! the cells decided by runs). Where the run to settlement gives the other decided label,
//! the rule group that decided the cell ([`Rules::of`] its reason) is refuted in that map.
//! [`act_on_audits`] then, for each map of the shard:
//! 1. records the refuted groups in the sink, with why ([`Sink::write_withdrawn`]), before
//!    anything else: a scan interrupted after this point knows them when resumed;
//! 2. prepares the map without every group recorded for it
//!    ([`MapContext::prepare_without`]) and decides again each stored cell whose reason
//!    belongs to one of them (its audit too, if it is in the sample), storing each block
//!    again ([`Sink::write_block`] replaces the block);
//! 3. repeats while the redone cells' audits refute another group (at most once per group).
//!
//! It is idempotent: a redone cell no longer carries a withdrawn group's reason, so a
//! resumed scan that stopped half-way redoes only the blocks not yet stored again. Cells of
//! other shards are theirs to redo (each shard acts on its own audits).

use rayon::prelude::*;
use squeal_core::Reason;

use crate::cell::{Audit, Cell};
use crate::census::Rules;
use crate::driver::{Computed, DriveError, Shard, Sink, shard_owns};
use crate::scanner::{BlockResult, MapContext, Withdrawn};
use crate::spec::Plan;

/// What the audit did to one map.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Acted {
    /// The map.
    pub map: usize,
    /// Cells decided again.
    pub cells: usize,
}

/// Whether the cell's run to settlement gave the other decided label
/// ([`Audit::Disagrees`]): what refutes a rule.
pub(crate) fn disagrees(c: &Cell) -> bool {
    c.audit == Audit::Disagrees as u8
}

/// The rule group of a stored cell's reason, if an early rule decided it.
fn group(c: &Cell) -> Option<Rules> {
    Reason::ALL
        .get(c.reason as usize)
        .copied()
        .and_then(Rules::of)
}

/// Refuted groups of block `block` of `plan` not yet in `known`: the groups of its audited
/// cells whose run to settlement gave the other decided label, each with the first such
/// cell as why.
fn refuted(plan: &Plan, block: usize, cells: &[Cell], known: &[Withdrawn]) -> Vec<Withdrawn> {
    let g = &plan.map.grid;
    let rows = g.block_rows(block);
    let mut out: Vec<Withdrawn> = Vec::new();
    for (k, c) in cells.iter().enumerate() {
        if !disagrees(c) {
            continue;
        }
        let Some(rules) = group(c) else { continue };
        if known.iter().chain(&out).any(|w| w.rules == rules) {
            continue;
        }
        let (x, v) = g.state(rows.start + k / g.x0.count, k % g.x0.count);
        let label = c.regime().map_or("?", |r| r.name());
        let reason = Reason::ALL[c.reason as usize].name();
        out.push(Withdrawn {
            rules,
            why: format!(
                "{} withdrawn by the audit: the run to settlement from ({x:.6}, {v:.6}) \
                 contradicts its label {label} by {reason}",
                rules.name()
            ),
        });
    }
    out
}

/// The blocks of map `m` among `blocks` whose audits can refute a rule: those `computed`
/// marks disagreeing, and every block it does not hold (all, without it).
fn to_search(blocks: &[usize], m: usize, computed: Option<&Computed>) -> Vec<usize> {
    let keep = |b: usize| {
        computed.is_none_or(|c| !c.blocks.contains(&(m, b)) || c.disagreeing.contains(&(m, b)))
    };
    blocks.iter().copied().filter(|&b| keep(b)).collect()
}

/// Acts on the audits of every map `shard` owns in `sink` (see the module's overview): the
/// maps where cells were decided again, with how many. `computed`: the blocks the drive
/// into this `sink` just computed ([`crate::DriveReport::computed`]), or `None`.
///
/// Which blocks are searched for refuting audits: a refuted group comes from a cell whose
/// audit disagrees, so of the blocks `computed` holds only those it marks disagreeing are
/// read; every other block (stored by an earlier run, `None`: all) is read. Each block
/// yields all its new groups in one reading, so a later round reads only the blocks the
/// round before decided again (their audits are new). On the 4096 x 4096 map of
/// `scans/fig9.toml` the first reading of every block took 2.8 s on one thread.
pub fn act_on_audits<S: Sink>(
    plan: &Plan,
    shard: Option<Shard>,
    sink: &mut S,
    computed: Option<&Computed>,
) -> Result<Vec<Acted>, DriveError<S::Error>> {
    let g = &plan.map.grid;
    let mut acted = Vec::new();
    for m in 0..plan.maps.len() {
        let blocks: Vec<usize> = (0..g.blocks())
            .filter(|&b| shard_owns(shard, plan, m, b))
            .collect();
        let mut search = to_search(&blocks, m, computed);
        let mut redone = 0usize;
        for _round in 0..=Rules::ALL.len() {
            let mut known = sink.withdrawn(m).map_err(DriveError::Sink)?;
            let mut found = Vec::new();
            for &b in &search {
                if let Some(cells) = sink.stored_block(m, b).map_err(DriveError::Sink)? {
                    let mut all = known.clone();
                    all.extend(found.iter().cloned());
                    found.extend(refuted(plan, b, &cells, &all));
                }
            }
            if !found.is_empty() {
                sink.write_withdrawn(m, &found).map_err(DriveError::Sink)?;
                known.extend(found);
            }
            if known.is_empty() {
                // Nothing withdrawn, so no cell to decide again: the map's blocks are not
                // read back a second time (on a 4096 x 4096 map that read was half of the
                // 13 s this step took).
                break;
            }
            let gone = |c: &Cell| group(c).is_some_and(|r| known.iter().any(|w| w.rules == r));
            let mut ctx: Option<MapContext> = None;
            let mut rewritten = Vec::new();
            for &b in &blocks {
                let Some(mut cells) = sink.stored_block(m, b).map_err(DriveError::Sink)? else {
                    continue;
                };
                if !cells.iter().any(gone) {
                    continue;
                }
                if ctx.is_none() {
                    ctx = Some(MapContext::prepare_without(plan, m, &known)?);
                }
                let ctx = ctx.as_ref().expect("prepared above");
                let rows = g.block_rows(b);
                let nx = g.x0.count;
                let again: Vec<(usize, Cell)> = cells
                    .par_iter()
                    .enumerate()
                    .filter(|(_, c)| gone(c))
                    .map(|(k, _)| (k, ctx.cell(plan, rows.start + k / nx, k % nx)))
                    .collect();
                redone += again.len();
                for (k, c) in again {
                    cells[k] = c;
                }
                rewritten.push(b);
                sink.write_block(&BlockResult {
                    map: m,
                    block: b,
                    cells,
                })
                .map_err(DriveError::Sink)?;
            }
            if rewritten.is_empty() {
                break;
            }
            search = rewritten;
        }
        let cells = redone;
        acted.extend((cells > 0).then_some(Acted { map: m, cells }));
    }
    Ok(acted)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::driver::MemorySink;

    /// Fig. 9's model on a 4 x 3 grid over its box, in blocks of one row: every start lies
    /// outside the unstable cycle and is labelled by the start rule.
    ///
    /// The leak these tests act on used to be the README's clamped disc brake at c = 300 N s/m,
    /// where the start rule labelled starts stick-slip and their runs ended quiet. Steady
    /// slip repels there (k = 1.1355 > 1, crates/core/MODEL.md section 5): the section search
    /// now finds no cycle and no start rule applies, so no model on record makes the audit
    /// disagree. The audit's finding is therefore injected ([`unchecked`]), and what is
    /// tested is what acting on it does.
    fn brake() -> Plan {
        let mut plan = Plan::from_toml(
            r#"version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -3.0, max = 5.0, count = 4 }
v0 = { min = -4.0, max = 4.0, count = 3 }
[classifier]
t_max = 2000.0
[output]
path = "t.h5"
"#,
            "t.toml",
        )
        .unwrap();
        plan.map.grid.block_rows = 1;
        plan
    }

    /// The blocks of `plan`'s map 0 as a map without its census computes them, with the
    /// audit's finding injected: every audited cell the outside rules decided reads
    /// `disagrees`, as where its run to settlement reached the fixed point.
    fn unchecked(plan: &Plan) -> MemorySink {
        let ctx = MapContext::prepare_checked(plan, 0, crate::scanner::Checks::NoCensus).unwrap();
        let mut sink = MemorySink::default();
        for b in 0..plan.map.grid.blocks() {
            let mut r = crate::scanner::run_block(plan, &ctx, b, &crate::NoObserver, None).unwrap();
            for c in r.cells.iter_mut() {
                if group(c) == Some(Rules::Outside) && c.audit != Audit::NotAudited as u8 {
                    c.audit = Audit::Disagrees as u8;
                }
            }
            sink.blocks.insert((0, b), r);
        }
        sink
    }

    fn cells(sink: &MemorySink, plan: &Plan) -> Vec<Cell> {
        sink.map_cells(plan, 0).unwrap()
    }

    /// No scan may end with a DISAGREEMENT whose cells keep refuted labels. Every
    /// cell of this small map is audited (fewer than AUDIT_PER_RULE per rule), and the audit's
    /// finding against the outside rules is injected ([`unchecked`]); acting on it withdraws
    /// the outside rules, records why,
    /// and decides every cell they decided again: none keeps their reason or a disagreeing
    /// audit. A second pass finds nothing to do, and a pass interrupted after recording the
    /// withdrawal (a resume) ends with the same cells.
    #[test]
    fn a_refuted_rule_is_withdrawn_and_its_cells_decided_again() {
        let plan = brake();
        let before = unchecked(&plan);
        let outside = |c: &Cell| group(c) == Some(Rules::Outside);
        let disagrees = |c: &Cell| c.audit == Audit::Disagrees as u8;
        assert!(
            cells(&before, &plan).iter().any(disagrees),
            "the audit sees the leak"
        );
        assert!(cells(&before, &plan).iter().any(outside));
        let mut sink = before.clone();
        let acted = act_on_audits(&plan, None, &mut sink, None).unwrap();
        assert_eq!(acted.len(), 1, "{acted:?}");
        let w = &sink.withdrawn[&0];
        assert!(w.iter().any(|w| w.rules == Rules::Outside), "{w:?}");
        assert!(w[0].why.contains("withdrawn by the audit"), "{w:?}");
        let after = cells(&sink, &plan);
        assert!(!after.iter().any(outside), "{after:?}");
        assert!(!after.iter().any(disagrees), "{after:?}");
        assert!(
            act_on_audits(&plan, None, &mut sink.clone(), None)
                .unwrap()
                .is_empty()
        );
        // Interrupted once the withdrawal was recorded, before any block was stored again.
        let mut resumed = before.clone();
        resumed.withdrawn.insert(0, w.clone());
        act_on_audits(&plan, None, &mut resumed, None).unwrap();
        let labels = |c: Vec<Cell>| c.iter().map(|c| c.regime).collect::<Vec<_>>();
        assert_eq!(labels(cells(&resumed, &plan)), labels(after));
    }

    /// What a drive computed narrows the search: with the blocks it marks disagreeing, the
    /// audit acts exactly as when every block is read; a block it computed without such a
    /// cell is not read at all (marked computed and not disagreeing, the leak of
    /// `a_refuted_rule_is_withdrawn_and_its_cells_decided_again` goes unseen, which shows
    /// the mark is what is consulted: the drive must set it truthfully, as `drive` does).
    #[test]
    fn the_search_reads_only_the_computed_blocks_that_disagree() {
        let plan = brake();
        let before = unchecked(&plan);
        let all: Vec<(usize, usize)> = (0..plan.map.grid.blocks()).map(|b| (0, b)).collect();
        let disagreeing = (all.iter().copied())
            .filter(|&(m, b)| before.blocks[&(m, b)].cells.iter().any(disagrees))
            .collect();
        assert!(!before.blocks.is_empty());
        let truthful = Computed {
            blocks: all.iter().copied().collect(),
            disagreeing,
        };
        let (mut read_all, mut narrowed) = (before.clone(), before.clone());
        let a = act_on_audits(&plan, None, &mut read_all, None).unwrap();
        let b = act_on_audits(&plan, None, &mut narrowed, Some(&truthful)).unwrap();
        assert_eq!(a, b);
        // Bit for bit (NaN fields: compared as written).
        let shown = |s: &MemorySink| format!("{:?}", cells(s, &plan));
        assert_eq!(shown(&read_all), shown(&narrowed));
        assert_eq!(read_all.withdrawn, narrowed.withdrawn);
        let silent = Computed {
            blocks: all.into_iter().collect(),
            disagreeing: Default::default(),
        };
        let mut unread = before.clone();
        assert!(
            act_on_audits(&plan, None, &mut unread, Some(&silent))
                .unwrap()
                .is_empty()
        );
    }
}
