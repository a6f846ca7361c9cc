//! A fingerprint of the sources that produced a table, so that a stale table is found.

use std::path::Path;

use crate::SelectError;

/// 64-bit FNV-1a offset basis.
const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
/// 64-bit FNV-1a prime.
const FNV_PRIME: u64 = 0x0100_0000_01b3;

fn fnv1a(mut hash: u64, bytes: &[u8]) -> u64 {
    for &byte in bytes {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(FNV_PRIME);
    }
    hash
}

/// The FNV-1a hash (16 hex digits) of the files under `paths`, relative to `root`: each
/// path a file or a folder (walked whole), every file hashed with its relative path, in
/// sorted order, so that the fingerprint changes when any byte, name or file changes and
/// depends on nothing else (not on dates or the order of the folder listing).
///
/// An error names a path that cannot be read, or a `paths` entry that is neither a file
/// nor a folder.
pub fn fingerprint(root: &Path, paths: &[&str]) -> Result<String, SelectError> {
    let io =
        |path: &Path, e: std::io::Error| SelectError::Io { path: path.display().to_string(), reason: e.to_string() };
    let mut files = Vec::new();
    let mut pending: Vec<std::path::PathBuf> = paths.iter().map(|p| root.join(p)).collect();
    while let Some(path) = pending.pop() {
        let metadata = std::fs::metadata(&path).map_err(|e| io(&path, e))?;
        if metadata.is_dir() {
            for entry in std::fs::read_dir(&path).map_err(|e| io(&path, e))? {
                pending.push(entry.map_err(|e| io(&path, e))?.path());
            }
        } else if metadata.is_file() {
            files.push(path);
        } else {
            return Err(SelectError::Io { path: path.display().to_string(), reason: "not a file or folder".into() });
        }
    }
    let relative = |path: &Path| path.strip_prefix(root).unwrap_or(path).to_string_lossy().replace('\\', "/");
    files.sort_by_key(|p| relative(p));
    files.dedup();
    let mut hash = FNV_OFFSET;
    for file in &files {
        hash = fnv1a(hash, relative(file).as_bytes());
        hash = fnv1a(hash, &[0]);
        hash = fnv1a(hash, &std::fs::read(file).map_err(|e| io(file, e))?);
        hash = fnv1a(hash, &[0]);
    }
    Ok(format!("{hash:016x}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_its_published_test_vectors() {
        // From the FNV reference (Fowler, Noll & Vo): "" and "a".
        assert_eq!(fnv1a(FNV_OFFSET, b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(FNV_OFFSET, b"a"), 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn the_fingerprint_follows_contents_and_names_but_not_listing_order() {
        let root = std::env::temp_dir().join(format!("model-select-fingerprint-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(root.join("src/deep")).unwrap();
        std::fs::write(root.join("src/a.rs"), "fn a() {}").unwrap();
        std::fs::write(root.join("src/deep/b.rs"), "fn b() {}").unwrap();
        std::fs::write(root.join("c.toml"), "x = 1").unwrap();
        let first = fingerprint(&root, &["src", "c.toml"]).unwrap();
        assert_eq!(first.len(), 16);
        assert_eq!(fingerprint(&root, &["c.toml", "src"]).unwrap(), first);
        std::fs::write(root.join("src/deep/b.rs"), "fn b() { }").unwrap();
        let edited = fingerprint(&root, &["src", "c.toml"]).unwrap();
        assert_ne!(edited, first);
        std::fs::rename(root.join("src/a.rs"), root.join("src/a2.rs")).unwrap();
        assert_ne!(fingerprint(&root, &["src", "c.toml"]).unwrap(), edited);
        let error = fingerprint(&root, &["missing.rs"]).unwrap_err().to_string();
        assert!(error.contains("missing.rs"), "{error}");
        std::fs::remove_dir_all(&root).unwrap();
    }
}
