//! End-to-end tests: the `squeal` binary run in temporary folders, its files reopened.
//! One test binary (a module per subject), so that cargo builds and links it once.

mod atlas;
mod atlas_files;
mod atlas_laws;
mod atlas_maps;
mod basin_stability;
mod bstab_friction;
mod cli_core;
mod cli_doc;
mod cli_fifos;
mod cli_files;
mod cli_hostile;
mod cli_hostile_msgs;
mod cli_kinds_rows;
mod cli_scan_cases;
mod cli_ulc_critical;
mod first_use;
mod fuzz;
mod fuzz_units;
mod physical_clamp;
mod physical_outputs;
mod plot_script;
mod report;
mod run_ends;
mod same_content;
mod scan;
mod scan_laws;
mod scan_sweeps;
mod stored_specs;
mod table_law;
mod trajectory_files;
mod unit_slips;
