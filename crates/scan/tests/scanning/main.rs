//! The scan crate's tests: specs, shortcuts and labels against runs and the paper. One test
//! binary, a module per subject, so that cargo builds and links it once.

mod accuracy;
mod edge;
mod fold_crisis;
mod fold_truth;
mod hostile;
mod off_paper;
mod science;
mod shipped_mutations;
mod shortcuts;
mod spec_doc;
mod table_spec;
mod transient;
mod unstable_steady;
