//! File-system helpers shared by presets and exporters.

use std::cell::Cell;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

thread_local! {
    /// Bytes this thread's atomic writes may write before failing as a
    /// full disk does; `None`: no fault ([`inject_full_disk`]).
    static FULL_DISK_AFTER: Cell<Option<usize>> = const { Cell::new(None) };
}

/// Makes this thread's atomic writes fail after `after_bytes` bytes with
/// the error a full disk gives (ENOSPC), or stop failing (`None`). For
/// tests: nothing in the editor or the command line turns it on.
#[doc(hidden)]
pub fn inject_full_disk(after_bytes: Option<usize>) {
    FULL_DISK_AFTER.with(|f| f.set(after_bytes));
}

/// Writes `bytes` to `f`, failing as a full disk would where a test asked.
fn write_all_or_full(f: &mut fs::File, bytes: &[u8]) -> std::io::Result<()> {
    match FULL_DISK_AFTER.with(Cell::get) {
        Some(n) if n < bytes.len() => {
            f.write_all(&bytes[..n])?;
            #[cfg(unix)]
            let full = std::io::Error::from_raw_os_error(28);
            #[cfg(not(unix))]
            let full = std::io::Error::from(std::io::ErrorKind::StorageFull);
            Err(full)
        }
        _ => f.write_all(bytes),
    }
}

/// Writes `bytes` to `path` atomically: a temporary file in the same
/// directory is written, flushed to disk and renamed over the target, so a
/// crash or a full disk never leaves a half-written file behind.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("output");
    let tmp: PathBuf = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut f = fs::File::create(&tmp)?;
        write_all_or_full(&mut f, bytes)?;
        f.sync_all()?;
        fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        let _ = fs::remove_file(&tmp);
        // Say what the failure did not do: every caller's message has it.
        std::io::Error::new(
            e.kind(),
            format!("{e}; nothing was written, and any file already there is unchanged"),
        )
    })
}

/// What is wrong with a file of `len` bytes that needs at least `need`
/// to hold `what`: "0 bytes: the file is empty", or "N bytes: too short
/// for WHAT"; `None` when it is long enough.
pub fn too_short(len: u64, need: u64, what: &str) -> Option<String> {
    match len {
        0 => Some("0 bytes: the file is empty".into()),
        n if n < need => Some(format!("{n} bytes: too short for {what}")),
        _ => None,
    }
}

/// The size of the file at `path`, for the checks before reading it.
pub fn file_len(path: &Path) -> std::io::Result<u64> {
    fs::metadata(path).map(|m| m.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_files_are_named_by_their_size() {
        assert_eq!(
            too_short(0, 12, "x").as_deref(),
            Some("0 bytes: the file is empty")
        );
        assert_eq!(
            too_short(5, 12, "a binary glTF header (12 bytes)").as_deref(),
            Some("5 bytes: too short for a binary glTF header (12 bytes)")
        );
        assert_eq!(too_short(12, 12, "x"), None);
    }

    #[test]
    fn replaces_whole_file_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("scatterlab-fsutil-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let p = dir.join("x.txt");
        write_atomic(&p, b"first version, long").unwrap();
        write_atomic(&p, b"second").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"second");
        let leftovers: Vec<_> = fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
            .collect();
        assert!(leftovers.is_empty());
        // A missing directory is an error, not a panic.
        assert!(write_atomic(&dir.join("missing/y.txt"), b"z").is_err());
        // A full disk half-way through: the old file stays whole, no
        // temporary is left, and the error says both.
        inject_full_disk(Some(3));
        let e = write_atomic(&p, b"third version").unwrap_err();
        inject_full_disk(None);
        assert_eq!(fs::read(&p).unwrap(), b"second");
        let text = e.to_string();
        assert!(text.contains("No space left on device"), "{text}");
        assert!(
            text.contains("any file already there is unchanged"),
            "{text}"
        );
        let tmp_left = fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .any(|e| e.file_name().to_string_lossy().ends_with(".tmp"));
        assert!(!tmp_left);
        fs::remove_dir_all(&dir).unwrap();
    }
}
