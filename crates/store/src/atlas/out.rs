//! The atlas writer's HDF5 plumbing: a file with its dimension scales, and the datasets
//! over a set of dimensions (the points, the boundaries, the maps' blocks...).

use hdf5::types::VarLenUnicode;
use hdf5::{Dataset, File, H5Type};
use ndarray::{ArrayD, IxDyn};

use crate::h5write::{Dims, str_attr};

/// The file being written and its dimension scales.
pub(super) struct Out<'a> {
    pub file: &'a File,
    pub dims: Dims,
}

/// The dimensions of a family of datasets: their shape and scales.
#[derive(Clone)]
pub(super) struct Over {
    pub shape: Vec<usize>,
    pub scales: Vec<Dataset>,
}

impl Over {
    /// These dimensions and one more, of length `n` with scale `scale`.
    pub(super) fn and(&self, n: usize, scale: &Dataset) -> Over {
        let mut o = self.clone();
        o.shape.push(n);
        o.scales.push(scale.clone());
        o
    }
}

impl Out<'_> {
    /// A dimension scale `name` holding `data`, with its long name and units.
    pub(super) fn scale<T: H5Type>(
        &mut self,
        name: &str,
        data: &[T],
        long: &str,
        units: Option<&str>,
    ) -> hdf5::Result<Dataset> {
        let ds = self
            .file
            .new_dataset_builder()
            .obj_track_times(false)
            .with_data(data)
            .create(name)?;
        str_attr(&ds, "long_name", long)?;
        if let Some(u) = units {
            str_attr(&ds, "units", u)?;
        }
        self.dims.scale(&ds, name)?;
        Ok(ds)
    }

    /// The index scale `0..n` named `name`.
    pub(super) fn index(&mut self, name: &str, n: usize, long: &str) -> hdf5::Result<Dataset> {
        let values: Vec<u64> = (0..n as u64).collect();
        self.scale(name, &values, long, None)
    }

    /// The dataset `name` over `over` holding `data` (C order), with its long name and
    /// units.
    pub(super) fn put<T: H5Type>(
        &mut self,
        over: &Over,
        (name, long): (&str, &str),
        units: Option<&str>,
        data: Vec<T>,
    ) -> hdf5::Result<Dataset> {
        let a = ArrayD::from_shape_vec(IxDyn(&over.shape), data)
            .map_err(|e| hdf5::Error::from(format!("{name}: {e}")))?;
        let ds = self
            .file
            .new_dataset_builder()
            .obj_track_times(false)
            .with_data(&a)
            .create(name)?;
        str_attr(&ds, "long_name", long)?;
        if let Some(u) = units {
            str_attr(&ds, "units", u)?;
        }
        let refs: Vec<&Dataset> = over.scales.iter().collect();
        self.dims.attach(self.file, &ds, &refs)?;
        Ok(ds)
    }

    /// [`Out::put`] of an enum with its CF flags (`meanings` of `values`).
    pub(super) fn put_flags<T: H5Type>(
        &mut self,
        over: &Over,
        named: (&str, &str),
        data: Vec<T>,
        (meanings, values): (&str, &[u8]),
    ) -> hdf5::Result<Dataset> {
        let ds = self.put(over, named, None, data)?;
        str_attr(&ds, "flag_meanings", meanings)?;
        ds.new_attr::<u8>()
            .shape(values.len())
            .create("flag_values")?
            .write_raw(values)?;
        Ok(ds)
    }

    /// [`Out::put`] of notes as strings, empty where there is none.
    pub(super) fn put_notes<'n>(
        &mut self,
        over: &Over,
        named: (&str, &str),
        notes: impl Iterator<Item = Option<&'n str>>,
    ) -> hdf5::Result<Dataset> {
        let v = notes
            .map(|n| {
                n.unwrap_or_default()
                    .parse::<VarLenUnicode>()
                    .map_err(|e| hdf5::Error::from(format!("note: {e}")))
            })
            .collect::<hdf5::Result<Vec<_>>>()?;
        self.put(over, named, None, v)
    }
}
