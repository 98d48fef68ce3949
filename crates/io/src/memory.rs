//! The memory this machine can give a new run, for the size checks of the commands and
//! the Python package before they allocate a result.

/// The memory this machine can give a new run, in bytes: `MemAvailable` plus `SwapFree`
/// of `/proc/meminfo` (Linux), lowered to what the process's own limits leave — its
/// address-space limit (`ulimit -v`, `/proc/self/limits`) less the address space it
/// uses (`VmSize` of `/proc/self/status`), and its control group's memory limit
/// (`memory.max` less `memory.current` in cgroup v2, `memory.limit_in_bytes` less
/// `memory.usage_in_bytes` in v1), as in a container — or `None` where `/proc/meminfo`
/// is missing or unreadable (then callers check nothing by default).
///
/// Read by hand: the numbers are one line each in text files, which no dependency is
/// needed for.
#[must_use]
pub fn available_memory() -> Option<u64> {
    let read = |path: &str| std::fs::read_to_string(path).ok();
    let machine = available_in_meminfo(&read("/proc/meminfo")?)?;
    let address_space = read("/proc/self/limits")
        .zip(read("/proc/self/status"))
        .and_then(|(limits, status)| address_space_left(&limits, &status));
    let group = cgroup_memory_left(&read);
    Some(
        [Some(machine), address_space, group]
            .into_iter()
            .flatten()
            .min()
            .unwrap_or(machine),
    )
}

/// The address space left under the soft `Max address space` limit of a
/// `/proc/self/limits` text, given the process's `VmSize` in a `/proc/self/status`
/// text, in bytes; `None` when the limit is `unlimited` or a line is missing.
#[must_use]
pub fn address_space_left(limits: &str, status: &str) -> Option<u64> {
    let line = limits
        .lines()
        .find(|l| l.starts_with("Max address space"))?;
    let soft = line["Max address space".len()..]
        .split_whitespace()
        .next()?;
    let limit: u64 = soft.parse().ok()?;
    let size = status.lines().find(|l| l.starts_with("VmSize:"))?;
    let size = kilobytes(size["VmSize:".len()..].trim())?;
    Some(limit.saturating_sub(size))
}

/// What the memory limit of the process's control group leaves, in bytes: cgroup v2
/// (`memory.max` and `memory.current` in the group named by the `0::` line of
/// `/proc/self/cgroup`), else v1 (`memory.limit_in_bytes` and `memory.usage_in_bytes`
/// of the memory controller); `None` without a limit (`max`, or v1's huge default) or
/// where the files cannot be read. `read` reads a file's text.
fn cgroup_memory_left(read: &dyn Fn(&str) -> Option<String>) -> Option<u64> {
    let number = |text: Option<String>| -> Option<u64> { text?.trim().parse().ok() };
    let groups = read("/proc/self/cgroup").unwrap_or_default();
    if let Some(path) = groups.lines().find_map(|l| l.strip_prefix("0::")) {
        let dir = format!("/sys/fs/cgroup{}", path.trim_end_matches('/'));
        if let Some(max) = number(read(&format!("{dir}/memory.max"))) {
            let current = number(read(&format!("{dir}/memory.current"))).unwrap_or(0);
            return Some(max.saturating_sub(current));
        }
    }
    let limit = number(read("/sys/fs/cgroup/memory/memory.limit_in_bytes"))?;
    // v1 writes a page-rounded i64::MAX when there is no limit.
    if limit >= 1 << 60 {
        return None;
    }
    let usage = number(read("/sys/fs/cgroup/memory/memory.usage_in_bytes")).unwrap_or(0);
    Some(limit.saturating_sub(usage))
}

/// `N kB` in bytes.
fn kilobytes(text: &str) -> Option<u64> {
    let number = text.strip_suffix("kB")?.trim();
    number.parse::<u64>().ok()?.checked_mul(1024)
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

    #[test]
    fn the_address_space_limit_less_what_is_used() {
        let limits = "Limit                     Soft Limit           Hard Limit           Units     \nMax stack size            8388608              unlimited            bytes     \nMax address space         4096000000           unlimited            bytes     \n";
        let status = "Name:\tbeltrami\nVmPeak:\t  200000 kB\nVmSize:\t  100000 kB\n";
        assert_eq!(
            address_space_left(limits, status),
            Some(4_096_000_000 - 100_000 * 1024)
        );
        let unlimited = limits.replace("4096000000", "unlimited");
        assert_eq!(address_space_left(&unlimited, status), None);
        assert_eq!(address_space_left(limits, "Name:\tx\n"), None);
    }

    #[test]
    fn a_control_groups_limit_less_its_usage() {
        let files = |v2: Option<(&'static str, &'static str)>,
                     v1: Option<(&'static str, &'static str)>| {
            move |path: &str| -> Option<String> {
                match path {
                    "/proc/self/cgroup" => Some(
                        if v2.is_some() {
                            "0::/box\n"
                        } else {
                            "4:memory:/box\n"
                        }
                        .to_string(),
                    ),
                    "/sys/fs/cgroup/box/memory.max" => v2.map(|(max, _)| max.to_string()),
                    "/sys/fs/cgroup/box/memory.current" => {
                        v2.map(|(_, current)| current.to_string())
                    }
                    "/sys/fs/cgroup/memory/memory.limit_in_bytes" => v1.map(|(l, _)| l.to_string()),
                    "/sys/fs/cgroup/memory/memory.usage_in_bytes" => v1.map(|(_, u)| u.to_string()),
                    _ => None,
                }
            }
        };
        let left = |v2, v1| cgroup_memory_left(&files(v2, v1));
        assert_eq!(left(Some(("1000000\n", "250000\n")), None), Some(750_000));
        assert_eq!(left(Some(("max\n", "250000\n")), None), None);
        assert_eq!(left(None, Some(("2000000", "500000"))), Some(1_500_000));
        assert_eq!(left(None, Some(("9223372036854771712", "500000"))), None);
        assert_eq!(left(None, None), None);
    }
}
