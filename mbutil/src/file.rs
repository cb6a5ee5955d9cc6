//! Reading a user's file (a `.moos` or `.bhv`) without being stalled or flooded by it.

use std::io::{Error, ErrorKind, Read};
use std::path::Path;

/// The file's bytes, reading at most `max + 1` (so a huge file or `/dev/zero` cannot
/// exhaust memory): `Ok(None)` if there was more than `max`. A FIFO or a socket is
/// refused before it is opened: opening one waits for a writer, possibly forever.
pub fn read_capped(path: &Path, max: u64) -> std::io::Result<Option<Vec<u8>>> {
    refuse_blocking(path)?;
    let mut buf = Vec::new();
    std::fs::File::open(path)?
        .take(max.saturating_add(1))
        .read_to_end(&mut buf)?;
    Ok((buf.len() as u64 <= max).then_some(buf))
}

#[cfg(unix)]
fn refuse_blocking(path: &Path) -> std::io::Result<()> {
    use std::os::unix::fs::FileTypeExt;
    let Ok(meta) = std::fs::metadata(path) else {
        // Missing or unreadable: `open` gives the error worth showing.
        return Ok(());
    };
    let t = meta.file_type();
    if t.is_fifo() || t.is_socket() {
        let what = if t.is_fifo() { "a FIFO" } else { "a socket" };
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("is {what}, not a file (reading it would wait for a writer)"),
        ));
    }
    Ok(())
}

#[cfg(not(unix))]
fn refuse_blocking(_: &Path) -> std::io::Result<()> {
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("mbutil-file-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("scratch");
        d
    }

    #[test]
    fn reads_up_to_the_cap_and_says_when_there_is_more() {
        let d = scratch("cap");
        let p = d.join("f");
        std::fs::write(&p, b"12345").expect("write");
        assert_eq!(read_capped(&p, 5).expect("read"), Some(b"12345".to_vec()));
        assert_eq!(read_capped(&p, 4).expect("read"), None);
        assert!(read_capped(&d.join("missing"), 5).is_err());
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_is_refused_without_waiting() {
        let d = scratch("fifo");
        let p = d.join("pipe");
        let ok = std::process::Command::new("mkfifo")
            .arg(&p)
            .status()
            .is_ok_and(|s| s.success());
        if !ok {
            return; // no mkfifo here: nothing to test
        }
        let e = read_capped(&p, 10).expect_err("a FIFO");
        assert!(e.to_string().contains("FIFO"), "{e}");
    }
}
