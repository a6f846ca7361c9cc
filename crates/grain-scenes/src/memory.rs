//! The memory guard: a stacking's arrays are compared with the memory available before
//! they are allocated.

use crate::error::SceneError;

/// Bytes per grain of a [`crate::Stacking`]: `centre_scale` (16), `rotation` (16) and
/// `colour` (4).
pub const BYTES_PER_GRAIN: u64 = 16 + 16 + 4;

/// How much memory a stacking may take.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MemoryLimit {
    /// `MemAvailable` of `/proc/meminfo`; no limit where that file cannot be read (other
    /// systems), so the allocator decides.
    #[default]
    Available,
    /// An explicit number of bytes (tests, or a budget of the caller's).
    Bytes(u64),
    /// No limit: only the allocator decides.
    Unlimited,
}

impl MemoryLimit {
    /// The limit in bytes, `None` when there is none.
    pub fn bytes(self) -> Option<u64> {
        match self {
            MemoryLimit::Available => available_memory(),
            MemoryLimit::Bytes(b) => Some(b),
            MemoryLimit::Unlimited => None,
        }
    }

    /// `Ok` when `requested_bytes` fit in the limit, else [`SceneError::TooLarge`].
    pub fn check(self, requested_bytes: u64) -> Result<(), SceneError> {
        match self.bytes() {
            Some(available_bytes) if requested_bytes > available_bytes => {
                Err(SceneError::TooLarge { requested_bytes, available_bytes })
            }
            _ => Ok(()),
        }
    }
}

/// `MemAvailable` of `/proc/meminfo` in bytes, `None` when unreadable.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_meminfo(&text)
}

/// The `MemAvailable:` line of a `/proc/meminfo` text, in bytes.
fn parse_meminfo(text: &str) -> Option<u64> {
    let line = text.lines().find_map(|l| l.strip_prefix("MemAvailable:"))?;
    let mut words = line.split_whitespace();
    let value: u64 = words.next()?.parse().ok()?;
    let unit = match words.next() {
        Some("kB") => 1024,
        None => 1,
        Some(_) => return None,
    };
    value.checked_mul(unit)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meminfo_is_parsed() {
        let text = "MemTotal:       24000000 kB\nMemFree:  100 kB\nMemAvailable:   23000000 kB\n";
        assert_eq!(parse_meminfo(text), Some(23_000_000 * 1024));
        assert_eq!(parse_meminfo("MemFree: 3 kB\n"), None);
        assert_eq!(parse_meminfo("MemAvailable: x kB\n"), None);
    }

    #[test]
    fn explicit_limits_are_enforced() {
        assert!(MemoryLimit::Bytes(100).check(100).is_ok());
        assert_eq!(
            MemoryLimit::Bytes(100).check(101),
            Err(SceneError::TooLarge { requested_bytes: 101, available_bytes: 100 })
        );
        assert!(MemoryLimit::Unlimited.check(u64::MAX).is_ok());
    }
}
