//! A digest of a file's content, whatever its byte layout: the "same file" of tests and
//! comparisons.

use std::path::Path;

use hdf5::types::{
    FixedAscii, FloatSize, IntSize, TypeDescriptor, VarLenArray, VarLenAscii, VarLenUnicode,
};
use hdf5::{Container, File, Group, Location, ObjectReference1, ReferencedObject};

use crate::StoreError;
use crate::error::H5Ctx;
use crate::h5types::RefEntry;

/// 128-bit FNV-1a.
struct Hasher(u128);

impl Hasher {
    fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 ^= x as u128;
            self.0 = self
                .0
                .wrapping_mul(0x0000_0000_0100_0000_0000_0000_0000_013B);
        }
    }
    fn text(&mut self, s: &str) {
        self.bytes(&(s.len() as u64).to_le_bytes());
        self.bytes(s.as_bytes());
    }
}

fn ref_name(file: &File, r: &ObjectReference1) -> hdf5::Result<String> {
    Ok(match file.dereference(r)? {
        ReferencedObject::Dataset(d) => d.name(),
        ReferencedObject::Group(g) => g.name(),
        ReferencedObject::Datatype(_) => "<datatype>".into(),
    })
}

/// Hashes a dataset's or attribute's type, shape and values (references by target name).
fn hash_container(file: &File, c: &Container, h: &mut Hasher) -> hdf5::Result<()> {
    let d = c.dtype()?.to_descriptor()?;
    h.text(&d.to_string());
    h.text(&format!("{:?}", c.shape()));
    macro_rules! raw {
        ($t:ty) => {
            for v in c.read_raw::<$t>()? {
                h.bytes(&v.to_le_bytes());
            }
        };
    }
    match &d {
        TypeDescriptor::Unsigned(IntSize::U1) => raw!(u8),
        TypeDescriptor::Unsigned(IntSize::U2) => raw!(u16),
        TypeDescriptor::Unsigned(IntSize::U4) => raw!(u32),
        TypeDescriptor::Unsigned(IntSize::U8) => raw!(u64),
        TypeDescriptor::Integer(IntSize::U1) => raw!(i8),
        TypeDescriptor::Integer(IntSize::U2) => raw!(i16),
        TypeDescriptor::Integer(IntSize::U4) => raw!(i32),
        TypeDescriptor::Integer(IntSize::U8) => raw!(i64),
        TypeDescriptor::Float(FloatSize::U4) => raw!(f32),
        TypeDescriptor::Float(FloatSize::U8) => raw!(f64),
        TypeDescriptor::Enum(e) => match (e.size, e.signed) {
            (IntSize::U1, false) => raw!(u8),
            _ => raw!(i64),
        },
        TypeDescriptor::Boolean => raw!(u8),
        TypeDescriptor::VarLenUnicode => {
            for v in c.read_raw::<VarLenUnicode>()? {
                h.text(v.as_str());
            }
        }
        TypeDescriptor::VarLenAscii => {
            for v in c.read_raw::<VarLenAscii>()? {
                h.text(v.as_str());
            }
        }
        TypeDescriptor::FixedAscii(16) => {
            for v in c.read_raw::<FixedAscii<16>>()? {
                h.text(v.as_str());
            }
        }
        TypeDescriptor::VarLenArray(inner) if matches!(**inner, TypeDescriptor::Reference(_)) => {
            for v in c.read_raw::<VarLenArray<ObjectReference1>>()? {
                for r in v.iter() {
                    h.text(&ref_name(file, r)?);
                }
            }
        }
        TypeDescriptor::Compound(_) => {
            for v in c.read_raw::<RefEntry>()? {
                h.text(&ref_name(file, &v.dataset)?);
                h.bytes(&v.dimension.to_le_bytes());
            }
        }
        other => {
            return Err(hdf5::Error::from(format!(
                "content_digest: unsupported type {other}"
            )));
        }
    }
    Ok(())
}

fn hash_attrs(file: &File, loc: &Location, h: &mut Hasher) -> hdf5::Result<()> {
    let mut names = loc.attr_names()?;
    names.sort();
    for n in names {
        h.text(&n);
        let a = loc.attr(&n)?;
        hash_container(file, &a, h)?;
    }
    Ok(())
}

fn hash_group(file: &File, g: &Group, h: &mut Hasher) -> hdf5::Result<()> {
    hash_attrs(file, g, h)?;
    let mut names = g.member_names()?;
    names.sort();
    for n in names {
        h.text(&n);
        if let Ok(ds) = g.dataset(&n) {
            h.text("dataset");
            hash_attrs(file, &ds, h)?;
            hash_container(file, &ds, h)?;
        } else {
            h.text("group");
            hash_group(file, &g.group(&n)?, h)?;
        }
    }
    Ok(())
}

/// A digest of a file's content: every dataset's values and every attribute (names and
/// values) of every group, recursively; object references count by the name they point to.
/// Two files with the same digest hold the same data, whatever their byte layout.
pub fn content_digest(path: &Path) -> Result<String, StoreError> {
    let file = File::open(path).map_err(|e| StoreError::NotSquealFile {
        path: path.to_path_buf(),
        why: format!("cannot open it as HDF5: {e}"),
        advice: None,
    })?;
    let mut h = Hasher(0x6c62_272e_07bb_0142_62b8_2175_6295_c58d);
    hash_group(&file, &file, &mut h).h5(path)?;
    Ok(format!("{:032x}", h.0))
}
