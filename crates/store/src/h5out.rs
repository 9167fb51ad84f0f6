//! HDF5 plumbing shared by the writers: string and number attributes, dimension scales
//! (netCDF-4 / HDF5 convention), and datasets over a set of dimensions ([`Out::put`]).

use std::path::Path;

use hdf5::types::{FixedAscii, VarLenArray, VarLenUnicode};
use hdf5::{Dataset, File, Group, H5Type, Location, ObjectReference1};
use ndarray::{ArrayD, IxDyn};

use crate::StoreError;
use crate::error::H5Ctx;
use crate::h5types::RefEntry;

pub(crate) fn str_attr(loc: &Location, name: &str, value: &str) -> hdf5::Result<()> {
    let v: VarLenUnicode = value
        .parse()
        .map_err(|e| hdf5::Error::from(format!("{e}")))?;
    loc.new_attr::<VarLenUnicode>()
        .create(name)?
        .write_scalar(&v)
}

pub(crate) fn num_attr<T: H5Type>(loc: &Location, name: &str, value: T) -> hdf5::Result<()> {
    loc.new_attr::<T>().create(name)?.write_scalar(&value)
}

/// The table law's table as small datasets at the root of `file` (nothing for other
/// laws): `friction_table_slip_speed` (nondimensional, the model's table `nd`),
/// `friction_table_slip_speed_si` (m/s, the measured curve `si` of a physical system) and
/// `friction_table_mu`, each with `long_name` and `units`, over the dimension `table_row` (a
/// scale, so xarray reads them). A physical scan or run stores both speeds (the same rows:
/// the SI ones over the velocity unit are the model's); a physical atlas only the SI ones
/// (each point has its own velocity unit). Datasets, not attributes: 10000 rows exceed an
/// attribute's 64 KiB.
pub(crate) fn friction_table(
    file: &File,
    dims: &mut Dims,
    nd: Option<&squeal_core::FrictionTable>,
    si: Option<&squeal_core::FrictionTable>,
) -> hdf5::Result<()> {
    let Some(t) = si.or(nd) else {
        return Ok(());
    };
    let speeds = [
        nd.map(|nd| {
            (
                "friction_table_slip_speed",
                nd.slip_speeds().to_vec(),
                "slip speed of the friction table's rows (natural-frequency velocity scale)",
                "1",
            )
        }),
        si.map(|si| {
            (
                "friction_table_slip_speed_si",
                si.slip_speeds().to_vec(),
                "slip speed of the friction table's rows, as measured",
                "m/s",
            )
        }),
    ];
    let sets = speeds.into_iter().flatten().chain([(
        "friction_table_mu",
        t.coefficients().to_vec(),
        "friction coefficient mu of the friction table's rows (PCHIP between them; the row at \
         slip speed 0 is the static coefficient)",
        "1",
    )]);
    let rows: Vec<u64> = (0..t.slip_speeds().len() as u64).collect();
    let row = dataset(
        file,
        "table_row",
        &rows[..],
        "row of the friction table",
        None,
    )?;
    dims.scale(&row, "table_row")?;
    for (name, data, long, units) in sets {
        let ds = dataset(file, name, &data[..], long, Some(units))?;
        dims.attach(file, &ds, &[&row])?;
    }
    Ok(())
}

/// Records dimension-scale attachments; `REFERENCE_LIST`s are written at the end.
pub(crate) struct Dims {
    pub(crate) scales: Vec<(Dataset, Vec<RefEntry>)>,
    /// The type of `CLASS`: a 16-byte null-terminated ASCII string, as `H5DSis_scale` demands.
    pub(crate) class_type: hdf5::Datatype,
}

/// A tiny HDF5 file (written with h5py) whose root attribute `CLASS` has the type the
/// dimension-scale API requires (fixed 16-byte ASCII, `H5T_STR_NULLTERM`). hdf5-metno can
/// only make null-padded fixed strings without `unsafe`, so the type is copied from here.
/// (Made with h5py: `t = h5py.h5t.C_S1.copy(); t.set_size(16);
/// t.set_strpad(h5py.h5t.STR_NULLTERM); f.attrs.create("CLASS", b"DIMENSION_SCALE",
/// dtype=h5py.Datatype(t))`, `libver="earliest"`. Named `.bin` because `.gitignore` drops `*.h5`.)
const CLASS_TEMPLATE: &[u8] = include_bytes!("dimension_scale_class.bin");

/// Reads the `CLASS` type from the template, written beside `path` for the moment.
pub(crate) fn class_type(path: &Path) -> Result<hdf5::Datatype, StoreError> {
    let mut s = path.as_os_str().to_owned();
    s.push(".class");
    let tpl = std::path::PathBuf::from(s);
    std::fs::write(&tpl, CLASS_TEMPLATE).map_err(crate::error::io(&tpl, "cannot write"))?;
    let t = (|| -> hdf5::Result<hdf5::Datatype> {
        let f = File::open(&tpl)?;
        let t = f.attr("CLASS")?.dtype()?;
        f.close()?;
        Ok(t)
    })()
    .h5(&tpl);
    let _ = std::fs::remove_file(&tpl);
    t
}

impl Dims {
    /// No scales yet; `class_type` from [`class_type`].
    pub(crate) fn new(class_type: hdf5::Datatype) -> Dims {
        Dims {
            scales: Vec::new(),
            class_type,
        }
    }

    /// Makes `ds` a dimension scale named `name` (netCDF-4 / HDF5 DS convention).
    pub(crate) fn scale(&mut self, ds: &Dataset, name: &str) -> hdf5::Result<()> {
        let class: FixedAscii<16> = FixedAscii::from_ascii("DIMENSION_SCALE")
            .map_err(|e| hdf5::Error::from(format!("{e}")))?;
        ds.new_attr_builder()
            .empty_as(&self.class_type)
            .create("CLASS")?
            .write_scalar(&class)?;
        let n: FixedAscii<16> =
            FixedAscii::from_ascii(name).map_err(|e| hdf5::Error::from(format!("{e}")))?;
        ds.new_attr::<FixedAscii<16>>()
            .create("NAME")?
            .write_scalar(&n)?;
        self.scales.push((ds.clone(), Vec::new()));
        Ok(())
    }

    /// Attaches scales (by dataset name) to the dimensions of `var`, in order.
    pub(crate) fn attach(
        &mut self,
        file: &File,
        var: &Dataset,
        scales: &[&Dataset],
    ) -> hdf5::Result<()> {
        let me: ObjectReference1 = file.reference(&var.name())?;
        let mut list = Vec::new();
        for (i, s) in scales.iter().enumerate() {
            let r: ObjectReference1 = file.reference(&s.name())?;
            list.push(VarLenArray::from_slice(&[r]));
            let entry = self
                .scales
                .iter_mut()
                .find(|(d, _)| d.name() == s.name())
                .ok_or_else(|| hdf5::Error::from("not a dimension scale"))?;
            entry.1.push(RefEntry {
                dataset: me,
                dimension: i as i32,
            });
        }
        var.new_attr::<VarLenArray<ObjectReference1>>()
            .shape(list.len())
            .create("DIMENSION_LIST")?
            .write_raw(&list)
    }

    pub(crate) fn finish(self) -> hdf5::Result<()> {
        for (ds, refs) in self.scales {
            if !refs.is_empty() {
                ds.new_attr::<RefEntry>()
                    .shape(refs.len())
                    .create("REFERENCE_LIST")?
                    .write_raw(&refs)?;
            }
        }
        Ok(())
    }
}

/// The file being written and its dimension scales.
pub(crate) struct Out<'a> {
    pub file: &'a File,
    pub dims: Dims,
    /// Auxiliary coordinates (CF): (path of the dimension scale, name of the variable over
    /// it), such as a physical scan's `x0_si` over `x0`. A variable [`Out::put`] then writes
    /// over one of those dimensions names them in its `coordinates` attribute.
    pub aux: Vec<(String, String)>,
}

/// The dimensions of a family of datasets: their shape and scales.
#[derive(Clone)]
pub(crate) struct Over {
    pub shape: Vec<usize>,
    pub scales: Vec<Dataset>,
}

impl Over {
    /// These dimensions and one more, of length `n` with scale `scale`.
    pub(crate) fn and(&self, n: usize, scale: &Dataset) -> Over {
        let mut o = self.clone();
        o.shape.push(n);
        o.scales.push(scale.clone());
        o
    }
}

impl Out<'_> {
    /// A dimension scale `name` holding `data`, with its long name and units.
    pub(crate) fn scale<T: H5Type>(
        &mut self,
        name: &str,
        data: &[T],
        long: &str,
        units: Option<&str>,
    ) -> hdf5::Result<Dataset> {
        let file = self.file;
        self.scale_in(file, name, (data, long, units))
    }

    /// [`Out::scale`] in group `g`.
    pub(crate) fn scale_in<T: H5Type>(
        &mut self,
        g: &Group,
        name: &str,
        (data, long, units): (&[T], &str, Option<&str>),
    ) -> hdf5::Result<Dataset> {
        let ds = dataset(g, name, data, long, units)?;
        self.dims.scale(&ds, name)?;
        Ok(ds)
    }

    /// The index scale `0..n` named `name` (in group `g`).
    pub(crate) fn index_in(
        &mut self,
        g: &Group,
        name: &str,
        n: usize,
        long: &str,
    ) -> hdf5::Result<Dataset> {
        let values: Vec<u64> = (0..n as u64).collect();
        self.scale_in(g, name, (&values, long, None))
    }

    /// The index scale `0..n` named `name`.
    pub(crate) fn index(&mut self, name: &str, n: usize, long: &str) -> hdf5::Result<Dataset> {
        let file = self.file;
        self.index_in(file, name, n, long)
    }

    /// The dataset `name` over `over` holding `data` (C order), with its long name and
    /// units.
    pub(crate) fn put<T: H5Type>(
        &mut self,
        over: &Over,
        named: (&str, &str),
        units: Option<&str>,
        data: Vec<T>,
    ) -> hdf5::Result<Dataset> {
        let file = self.file;
        self.put_in(file, over, named, units, data)
    }

    /// [`Out::put`] in group `g`.
    pub(crate) fn put_in<T: H5Type>(
        &mut self,
        g: &Group,
        over: &Over,
        (name, long): (&str, &str),
        units: Option<&str>,
        data: Vec<T>,
    ) -> hdf5::Result<Dataset> {
        let a = ArrayD::from_shape_vec(IxDyn(&over.shape), data)
            .map_err(|e| hdf5::Error::from(format!("{name}: {e}")))?;
        let ds = dataset(g, name, &a, long, units)?;
        let refs: Vec<&Dataset> = over.scales.iter().collect();
        self.dims.attach(self.file, &ds, &refs)?;
        self.declare_coordinates(&ds, over)?;
        Ok(ds)
    }

    /// Makes `aux` (a variable over the dimension scale `dim`) an auxiliary coordinate of
    /// every variable written over `dim` from now on.
    pub(crate) fn aux_coordinate(&mut self, dim: &Dataset, aux: &str) {
        self.aux.push((dim.name(), aux.to_string()));
    }

    /// The CF `coordinates` attribute of `ds` over `over`: the auxiliary coordinates over its
    /// dimensions, in the order declared (none: no attribute).
    pub(crate) fn declare_coordinates(&self, ds: &Dataset, over: &Over) -> hdf5::Result<()> {
        let dims: Vec<String> = over.scales.iter().map(|d| d.name()).collect();
        let names: Vec<&str> = (self.aux.iter())
            .filter(|(d, _)| dims.contains(d))
            .map(|(_, a)| a.as_str())
            .collect();
        if names.is_empty() {
            return Ok(());
        }
        str_attr(ds, "coordinates", &names.join(" "))
    }

    /// [`Out::put`] of an enum with its CF flags (`meanings` of `values`).
    pub(crate) fn put_flags<T: H5Type>(
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
    pub(crate) fn put_notes<'n>(
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

/// The dataset `name` in `g` holding `data`, with its long name and units.
fn dataset<'d, A, T, D>(
    g: &Group,
    name: &str,
    data: A,
    long: &str,
    units: Option<&str>,
) -> hdf5::Result<Dataset>
where
    A: Into<ndarray::ArrayView<'d, T, D>>,
    T: H5Type,
    D: ndarray::Dimension,
{
    let ds = g
        .new_dataset_builder()
        .obj_track_times(false)
        .with_data(data)
        .create(name)?;
    str_attr(&ds, "long_name", long)?;
    if let Some(u) = units {
        str_attr(&ds, "units", u)?;
    }
    Ok(ds)
}
