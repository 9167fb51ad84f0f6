//! Nothing to call: this crate's build script tells, during the first build of a profile,
//! that HDF5 is being compiled from source (docs/building.md); it has no dependencies, so
//! it does not wait for HDF5 as a build script of a crate using HDF5 would. squeal-store
//! depends on it so that every build that links HDF5 runs it.
