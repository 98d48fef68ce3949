//! The memory this machine can give a new run, for the size checks of the commands and
//! the Python package before they allocate a result.

/// The memory this machine can give a new run, in bytes: `MemAvailable` plus `SwapFree`
/// of `/proc/meminfo` (Linux), or `None` where that file is missing or unreadable (then
/// callers check nothing by default).
///
/// Read by hand: the two numbers are one line each in a text file, which no
/// dependency is needed for.
#[must_use]
pub fn available_memory() -> Option<u64> {
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| available_in_meminfo(&text))
}

/// `MemAvailable + SwapFree` of a `/proc/meminfo` text, in bytes (`SwapFree` counts 0
/// when absent); `None` without a readable `MemAvailable` line (kernels before 3.14).
#[must_use]
pub fn available_in_meminfo(text: &str) -> Option<u64> {
    let field = |name: &str| -> Option<u64> {
        let line = text.lines().find(|l| l.starts_with(name))?;
        let rest = line[name.len()..].trim();
        let (number, unit) = rest.split_once(' ').unwrap_or((rest, ""));
        let value: u64 = number.trim().parse().ok()?;
        match unit.trim() {
            "kB" => value.checked_mul(1024),
            "" => Some(value),
            _ => None,
        }
    };
    let available = field("MemAvailable:")?;
    Some(available.saturating_add(field("SwapFree:").unwrap_or(0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meminfo_gives_available_plus_free_swap() {
        let text = "MemTotal:       24000000 kB\nMemFree:         1000000 kB\nMemAvailable:   22000000 kB\nSwapTotal:       2000000 kB\nSwapFree:        1500000 kB\n";
        assert_eq!(
            available_in_meminfo(text),
            Some((22_000_000 + 1_500_000) * 1024)
        );
        let no_swap = "MemTotal: 24000000 kB\nMemAvailable: 100 kB\n";
        assert_eq!(available_in_meminfo(no_swap), Some(100 * 1024));
        assert_eq!(available_in_meminfo("MemTotal: 24000000 kB\n"), None);
        assert_eq!(available_in_meminfo("MemAvailable: lots kB\n"), None);
        assert_eq!(available_in_meminfo("MemAvailable: 5 MB\n"), None);
    }
}
