//! HDF5's direct chunk write (`H5Dwrite_chunk`): a chunk that geoslip filtered itself (shuffled
//! and deflated, `output/chunk_deflate.rs`) stored as it is, past the library's filter pipeline.
//! The one call into HDF5 that hdf5-metno does not wrap.

use hdf5::Dataset;

/// Store `bytes`, the whole chunk of `dataset` that starts at `offset` (one coordinate per
/// dimension, each a multiple of the chunk's extent), already passed through every filter of the
/// dataset's pipeline.
///
/// # Errors
/// HDF5's, when the offset is not a chunk's or the write fails.
pub fn write_chunk(dataset: &Dataset, offset: &[u64], bytes: &[u8]) -> hdf5::Result<()> {
    let rank = dataset.ndim();
    if offset.len() != rank {
        return Err(format!("a chunk offset of {} coordinates for a dataset of rank {rank}", offset.len()).into());
    }
    let id = dataset.id();
    // SAFETY: `id` is the open dataset that `dataset` owns for the length of the call;
    // `offset` holds one coordinate per dimension (checked above) and `bytes` is a live
    // buffer of `bytes.len()` bytes that HDF5 only reads. The filter mask 0 says every filter of
    // the pipeline was applied. The call holds hdf5-metno's lock, as all of its own calls do.
    let status = hdf5::sync::sync(|| unsafe {
        hdf5_sys::h5d::H5Dwrite_chunk(
            id,
            hdf5_sys::h5p::H5P_DEFAULT,
            0,
            offset.as_ptr(),
            bytes.len(),
            bytes.as_ptr().cast(),
        )
    });
    if status < 0 {
        return Err(format!("H5Dwrite_chunk failed for {} at {offset:?}", dataset.name()).into());
    }
    Ok(())
}
