//! Reading a file that may come from anyone: a model, a mesh, a calibration spec or its data.
//!
//! Only a regular file is read: a device (`/dev/zero`), a FIFO or a socket would be read without
//! end or would block, so it is refused before a byte is read. The file is opened without
//! blocking (a FIFO's open would otherwise wait for a writer), its kind is taken from the open
//! handle (not from the name, which could change between a look and the open), and it is read up
//! to a limit in bytes: a file that grows while it is read is refused at the limit, not followed.

use std::io::Read;
use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
use std::path::Path;

/// Why a file was not read. The caller names the file.
#[derive(Debug, thiserror::Error)]
pub enum Unreadable {
    #[error("it is {0}; geoslip reads regular files only")]
    NotRegular(&'static str),
    #[error("it is {size_mb:.1} MB and this run may read {limit_mb:.1} MB ({why})")]
    TooLarge { size_mb: f64, limit_mb: f64, why: &'static str },
    #[error("{0}")]
    Io(#[from] std::io::Error),
}

/// The most a file may hold: a number of bytes, with what it comes from for the message.
#[derive(Debug, Clone, Copy)]
pub struct SizeLimit {
    pub bytes: u64,
    pub why: &'static str,
}

impl SizeLimit {
    /// The run's memory limit (`--memory-limit`, MB), or the memory this machine has available
    /// now when none is given, or 4 GB when neither is known.
    pub fn of_memory(limit_mb: Option<f64>) -> SizeLimit {
        match limit_mb.filter(|m| m.is_finite() && *m > 0.0) {
            Some(mb) => SizeLimit { bytes: (mb * 1048576.0) as u64, why: "--memory-limit" },
            None => match crate::memory::available_memory_mb() {
                Some(mb) => SizeLimit { bytes: (mb * 1048576.0) as u64, why: "the memory this machine has available" },
                None => SizeLimit { bytes: 4 << 30, why: "4 GB when the machine's memory is not known" },
            },
        }
    }
}

/// The whole of a regular file, at most `limit` bytes of it.
///
/// # Errors
/// [`Unreadable`]: not a regular file, larger than the limit, or an I/O error.
pub fn read(path: &Path, limit: SizeLimit) -> Result<Vec<u8>, Unreadable> {
    read_with(path, limit, libc::O_NONBLOCK)
}

/// [`read`], refusing a path whose last component is a symbolic link (a file that a confined
/// program wrote, which could otherwise point anywhere).
///
/// # Errors
/// As [`read`]; a link is an I/O error (ELOOP).
pub fn read_not_linked(path: &Path, limit: SizeLimit) -> Result<Vec<u8>, Unreadable> {
    read_with(path, limit, libc::O_NONBLOCK | libc::O_NOFOLLOW)
}

fn read_with(path: &Path, limit: SizeLimit, flags: i32) -> Result<Vec<u8>, Unreadable> {
    let file = std::fs::OpenOptions::new().read(true).custom_flags(flags).open(path)?;
    let meta = file.metadata()?;
    let kind = meta.file_type();
    if !kind.is_file() {
        return Err(Unreadable::NotRegular(if kind.is_dir() {
            "a folder"
        } else if kind.is_fifo() {
            "a FIFO (named pipe)"
        } else if kind.is_char_device() || kind.is_block_device() {
            "a device"
        } else if kind.is_socket() {
            "a socket"
        } else {
            "not a regular file"
        }));
    }
    let too_large = |size: u64| Unreadable::TooLarge {
        size_mb: size as f64 / 1048576.0,
        limit_mb: limit.bytes as f64 / 1048576.0,
        why: limit.why,
    };
    if meta.len() > limit.bytes {
        return Err(too_large(meta.len()));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit.bytes.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit.bytes {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMIT: SizeLimit = SizeLimit { bytes: 1000, why: "a test" };

    #[test]
    fn a_device_a_fifo_and_a_folder_are_refused_before_reading() {
        assert!(matches!(read(Path::new("/dev/zero"), LIMIT), Err(Unreadable::NotRegular("a device"))));
        let dir = tempfile::tempdir().unwrap();
        assert!(matches!(read(dir.path(), LIMIT), Err(Unreadable::NotRegular("a folder"))));
        let fifo = dir.path().join("pipe");
        let status = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(status.success());
        // no writer: a blocking open would wait here for ever
        assert!(matches!(read(&fifo, LIMIT), Err(Unreadable::NotRegular("a FIFO (named pipe)"))));
    }

    #[test]
    fn a_file_is_read_whole_up_to_the_limit_and_refused_above_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("model.toml");
        std::fs::write(&path, vec![b'x'; 1000]).unwrap();
        assert_eq!(read(&path, LIMIT).unwrap().len(), 1000);
        std::fs::write(&path, vec![b'x'; 1001]).unwrap();
        let e = read(&path, LIMIT).unwrap_err();
        assert!(e.to_string().contains("a test"), "{e}");
    }

    #[test]
    fn a_memory_limit_that_is_not_a_positive_number_is_not_a_limit_of_zero() {
        assert!(SizeLimit::of_memory(Some(f64::NAN)).bytes > 0);
        assert_eq!(SizeLimit::of_memory(Some(2.0)).bytes, 2 * 1048576);
    }
}
