//! How `results.h5` stores its arrays: mesh tables and ids whole or chunked by rows, the step
//! fields each column chunked apart and filtered here (`chunk_deflate.rs`), the history's
//! datasets that grow by an entry a step, and the groups and attributes around them.

use super::chunk_deflate::ChunkDeflater;
use super::options::FieldPrecision;
use super::xdmf::{DataRef, NumberType};
use crate::native::hdf5_chunk;
use hdf5::types::VarLenUnicode;
use hdf5::{Dataset, Group, H5Type, Location};
use std::cell::RefCell;

/// Values per chunk of a field dataset (256 KiB of f64).
const CHUNK_VALUES: usize = 32_768;
/// Below this many values a dataset is stored whole and uncompressed: a chunk index and a filter
/// pipeline would cost more than they save.
const SMALL_VALUES: usize = 512;
/// Entries per chunk of a history dataset.
const HISTORY_CHUNK: usize = 256;
/// Deflate level 1: on a 10⁴-unknown pull-out the file is 0.5 % larger than at level 4 and written
/// in two thirds of the time. The step fields go through the shuffle filter first, each column of a
/// table (a tensor's component, a displacement's direction) chunked apart, so that the filter sees
/// one smoothly varying quantity at a time: on the same run's soil fields (docs/performance.md)
/// 12.1 MB instead of 14.7 in double precision and 5.5 instead of 7.4 in single. Mesh tables and
/// the history are compressed without it (whole rows a chunk: there the filter made the file
/// larger).
pub(super) const DEFLATE_LEVEL: u8 = 1;

/// Who filters a step field's chunks. The contract between geoslip's filter (`chunk_deflate.rs`:
/// the bytes shuffled by their size, then deflated at [`DEFLATE_LEVEL`] in zlib's format) and the
/// field dataset's filter pipeline (the shuffle filter, then deflate at the same level) is that a
/// chunk filtered either way is read back by libhdf5, and any HDF5 reader, as the same values.
/// `true`: geoslip filters the chunks and stores them past the pipeline (`native::hdf5_chunk`), an
/// all-zero chunk not at all (about twice as fast: docs/performance.md, "Results that take no
/// time"); `false`: the library's own filters do, from the same dataset definition.
pub(super) const OWN_CHUNK_FILTER: bool = true;

/// A numeric type of a dataset, with its XDMF number type.
pub(super) trait Stored: H5Type + Copy {
    const NUMBER: NumberType;
}
impl Stored for f64 {
    const NUMBER: NumberType = NumberType::Float8;
}
impl Stored for f32 {
    const NUMBER: NumberType = NumberType::Float4;
}
impl Stored for i32 {
    const NUMBER: NumberType = NumberType::Int4;
}
impl Stored for i64 {
    const NUMBER: NumberType = NumberType::Int8;
}
impl Stored for u64 {
    const NUMBER: NumberType = NumberType::UInt8;
}

/// Writes datasets, chunked and compressed when the library can.
pub(super) struct ArrayWriter<'a> {
    pub compress: bool,
    pub precision: FieldPrecision,
    pub deflater: &'a RefCell<ChunkDeflater>,
    /// Whether geoslip filters the field chunks itself ([`OWN_CHUNK_FILTER`]).
    pub own_filter: bool,
}

impl ArrayWriter<'_> {
    /// `data` as a `rows × columns` dataset `name` of `group` (one-dimensional for one column),
    /// with its `unit` as an attribute; when compressed, whole rows a chunk (the mesh, the ids,
    /// the states; the step fields go through [`ArrayWriter::field`]).
    pub(super) fn table<T: Stored>(
        &self,
        group: &Group,
        name: &str,
        data: &[T],
        columns: usize,
        unit: Option<&str>,
    ) -> hdf5::Result<DataRef> {
        let rows = data.len() / columns.max(1);
        let dims = if columns == 1 { vec![rows] } else { vec![rows, columns] };
        let mut builder = group.new_dataset::<T>().shape(dims.clone());
        if self.compress && data.len() >= SMALL_VALUES {
            let chunk = match columns {
                1 => vec![rows.min(CHUNK_VALUES)],
                _ => vec![rows.min((CHUNK_VALUES / columns).max(1)), columns],
            };
            builder = builder.chunk(chunk).deflate(DEFLATE_LEVEL);
        }
        let dataset = builder.create(name)?;
        if rows > 0 {
            dataset.write_raw(data)?;
        }
        if let Some(u) = unit {
            text_attr(&dataset, "unit", u)?;
        }
        Ok(DataRef { path: dataset.name(), dims, number: T::NUMBER })
    }

    /// A step field: `data` as a `rows × columns` dataset in the run's [`FieldPrecision`]. When
    /// compressed, each column is cut into chunks of its own (as many as `CHUNK_VALUES` makes
    /// needed, of equal rows), each filtered here and stored whole (`chunk_deflate.rs`), an
    /// all-zero chunk not at all.
    pub(super) fn field(
        &self,
        group: &Group,
        name: &str,
        data: &[f64],
        columns: usize,
        unit: Option<&str>,
    ) -> hdf5::Result<DataRef> {
        let compressed = self.compress && data.len() >= SMALL_VALUES;
        let (dataset, dims, number) = match (self.precision, compressed) {
            (FieldPrecision::Double, true) => {
                self.chunked_field::<f64, 8>(group, name, data, columns, |v| v, f64::to_ne_bytes)?
            }
            // each value rounded to the nearest single-precision number
            (FieldPrecision::Single, true) => {
                self.chunked_field::<f32, 4>(group, name, data, columns, |v| v as f32, |v| (v as f32).to_ne_bytes())?
            }
            // uncompressed (no deflate in the library) or too small to chunk
            (FieldPrecision::Double, false) => return self.table(group, name, data, columns, unit),
            (FieldPrecision::Single, false) => {
                let single: Vec<f32> = data.iter().map(|&v| v as f32).collect();
                return self.table(group, name, &single, columns, unit);
            }
        };
        if let Some(u) = unit {
            text_attr(&dataset, "unit", u)?;
        }
        Ok(DataRef { path: dataset.name(), dims, number })
    }

    /// `data` (`rows × columns`, each value in the dataset's type `T` as `value` gives it, its `S`
    /// bytes as `bytes` does) as a dataset behind the shuffle and deflate filters, a column a
    /// chunk, whose chunks are filtered here ([`OWN_CHUNK_FILTER`]) or by the library. Returns the
    /// dataset, its dimensions and its number type.
    fn chunked_field<T: Stored + Default, const S: usize>(
        &self,
        group: &Group,
        name: &str,
        data: &[f64],
        columns: usize,
        value: impl Fn(f64) -> T,
        bytes: impl Fn(f64) -> [u8; S],
    ) -> hdf5::Result<(Dataset, Vec<usize>, NumberType)> {
        let columns = columns.max(1);
        let rows = data.len() / columns;
        let chunk_rows = rows.div_ceil(rows.div_ceil(CHUNK_VALUES).max(1)).max(1);
        let (dims, chunk) =
            if columns == 1 { (vec![rows], vec![chunk_rows]) } else { (vec![rows, columns], vec![chunk_rows, 1]) };
        let dataset = group
            .new_dataset::<T>()
            .shape(dims.clone())
            .chunk(chunk)
            .shuffle()
            .deflate(DEFLATE_LEVEL)
            .fill_value(T::default())
            .create(name)?;
        if !self.own_filter {
            let values: Vec<T> = data.iter().map(|&v| value(v)).collect();
            if rows > 0 {
                dataset.write_raw(&values)?;
            }
            return Ok((dataset, dims, T::NUMBER));
        }
        // the table's columns one after another, each value as the dataset stores it, in one
        // pass over the rows (a column read alone from the rows would touch every row's cache
        // line once a column)
        let mut by_column = vec![[0u8; S]; rows * columns];
        for (row, values) in data.chunks_exact(columns).enumerate() {
            for (column, &v) in values.iter().enumerate() {
                by_column[column * rows + row] = bytes(v);
            }
        }
        let mut deflater = self.deflater.borrow_mut();
        for (column, values) in by_column.chunks_exact(rows.max(1)).enumerate() {
            for (k, chunk) in values.chunks(chunk_rows).enumerate() {
                let start = k * chunk_rows;
                let Some(deflated) = deflater.deflate(chunk, chunk_rows)? else { continue };
                let offset = if columns == 1 { vec![start as u64] } else { vec![start as u64, column as u64] };
                hdf5_chunk::write_chunk(&dataset, &offset, deflated)?;
            }
        }
        drop(deflater);
        Ok((dataset, dims, T::NUMBER))
    }

    /// An empty one-dimensional dataset that grows by one entry a step.
    pub(super) fn growing<T: Stored>(&self, group: &Group, name: &str) -> hdf5::Result<Dataset> {
        let mut builder = group.new_dataset::<T>().shape(0..).chunk(HISTORY_CHUNK);
        if self.compress {
            builder = builder.deflate(DEFLATE_LEVEL);
        }
        builder.create(name)
    }
}

/// A group of `parent`, without modification times.
pub(super) fn new_group(parent: &Group, name: &str) -> hdf5::Result<Group> {
    parent.create_group_builder().obj_track_times(false).create(name)
}

pub(super) fn text_attr(location: &Location, name: &str, value: &str) -> hdf5::Result<()> {
    let text: VarLenUnicode = value.replace('\0', "").parse().map_err(|e| hdf5::Error::from(format!("{e}")))?;
    location.new_attr::<VarLenUnicode>().create(name)?.write_scalar(&text)
}

pub(super) fn number_attr<T: H5Type>(location: &Location, name: &str, value: T) -> hdf5::Result<()> {
    location.new_attr::<T>().create(name)?.write_scalar(&value)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A field of several chunks a column, the last one short, with a column of zeros, written by
    /// `ArrayWriter::field` (chunks shuffled and deflated by geoslip, stored directly) and read
    /// back through libhdf5's own filter pipeline (its shuffle and its zlib inflate).
    #[test]
    fn a_field_of_many_chunks_reads_back_through_hdf5s_filters_value_for_value() {
        if !hdf5::filters::deflate_available() {
            return;
        }
        let dir = tempfile::tempdir().unwrap();
        let file = hdf5::File::create(dir.path().join("field.h5")).unwrap();
        let deflater = RefCell::new(ChunkDeflater::new(DEFLATE_LEVEL).unwrap());
        let rows = 2 * CHUNK_VALUES + 1001;
        // x: smooth with noise in the low bits; y: zeros, one negative zero; z: zeros
        let data: Vec<f64> = (0..rows)
            .flat_map(|i| {
                let x = (i as f64 * 1e-3).sin() * 1e-2 + (i as f64 * 7.77).fract() * 1e-9;
                let y = if i == 5 { -0.0 } else { 0.0 };
                [x, y, 0.0]
            })
            .collect();
        for (precision, own_filter) in
            [FieldPrecision::Single, FieldPrecision::Double].into_iter().flat_map(|p| [(p, true), (p, false)])
        {
            let w = ArrayWriter { compress: true, precision, deflater: &deflater, own_filter };
            let name = format!("{precision:?}-{own_filter}");
            let data_ref = w.field(&file, &name, &data, 3, Some("m")).unwrap();
            assert_eq!(data_ref.dims, vec![rows, 3]);
            let dataset = file.dataset(&name).unwrap();
            let chunk = dataset.chunk().unwrap();
            assert_eq!(chunk[1], 1, "a column a chunk");
            assert!(chunk[0] <= CHUNK_VALUES && rows.div_ceil(chunk[0]) == 3, "{chunk:?}");
            // geoslip's filter: x's three chunks and y's first (its negative zero); the other zero
            // chunks not stored. The library's: every chunk
            assert_eq!(dataset.num_chunks(), Some(if own_filter { 4 } else { 9 }), "own filter: {own_filter}");
            let filters = dataset.filters();
            assert!(filters.iter().any(|f| matches!(f, hdf5::filters::Filter::Shuffle)), "{filters:?}");
            assert!(filters.iter().any(|f| matches!(f, hdf5::filters::Filter::Deflate(_))), "{filters:?}");
            match precision {
                FieldPrecision::Single => {
                    let back: Vec<f32> = dataset.read_raw().unwrap();
                    assert_eq!(back.len(), data.len());
                    for (i, (a, b)) in back.iter().zip(&data).enumerate() {
                        assert!(a.to_bits() == (*b as f32).to_bits(), "[{}][{}]: {a} against {b}", i / 3, i % 3);
                    }
                }
                FieldPrecision::Double => {
                    let back: Vec<f64> = dataset.read_raw().unwrap();
                    for (i, (a, b)) in back.iter().zip(&data).enumerate() {
                        assert!(a.to_bits() == b.to_bits(), "[{}][{}]: {a} against {b}", i / 3, i % 3);
                    }
                }
            }
        }
    }
}
