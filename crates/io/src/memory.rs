//! The memory this machine can give a new run, for the size checks of the commands and
//! the Python package before they allocate a result.

/// The memory this machine can give a new run, in bytes: `MemAvailable` plus `SwapFree`
/// of `/proc/meminfo` (Linux), lowered to what the process's own limits leave — its
/// address-space limit (`ulimit -v`, `/proc/self/limits`) less the address space it
/// uses (`VmSize` of `/proc/self/status`), and its control group's memory limit less
/// the memory in use, reclaimable page cache not counted (cgroup v2 and v1, as in a
/// container or a batch job) — or `None` where `/proc/meminfo` is missing or
/// unreadable (then callers check nothing by default).
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

/// What the memory limit of the process's control group leaves, in bytes: the limit
/// less the memory in use, page cache the kernel can reclaim (`inactive_file`) not
/// counted as used — cgroup v2 (`memory.max`, `memory.current` and `memory.stat` of the
/// group named by the `0::` line of `/proc/self/cgroup`), else v1 (`memory.limit_in_bytes`,
/// `memory.usage_in_bytes` and `total_inactive_file` of the memory controller's group,
/// or of the hierarchy's root where that group is not mounted, as in a container);
/// with v2, the least left over the group and the groups above it (a parent's lower
/// limit binds too); `None` without a limit (`max`, or v1's huge default) or where the
/// files cannot be read. `read` reads a file's text. v1 parents are not read: the
/// figure can then only be too large, so no run is refused for it.
fn cgroup_memory_left(read: &dyn Fn(&str) -> Option<String>) -> Option<u64> {
    let number = |text: Option<String>| -> Option<u64> { text?.trim().parse().ok() };
    let stat = |path: &str, key: &str| -> u64 {
        read(path)
            .and_then(|text| {
                text.lines().find_map(|l| {
                    let (name, value) = l.split_once(' ')?;
                    (name == key).then(|| value.trim().parse().ok())?
                })
            })
            .unwrap_or(0)
    };
    let left = |limit: u64, usage: u64, reclaimable: u64| {
        limit.saturating_sub(usage.saturating_sub(reclaimable))
    };
    let groups = read("/proc/self/cgroup").unwrap_or_default();
    if let Some(path) = groups.lines().find_map(|l| l.strip_prefix("0::")) {
        // The group and every group above it: a parent's limit binds its children too,
        // and the least left of them is what a run can have.
        let mut path = path.trim_end_matches('/').to_string();
        let mut least: Option<u64> = None;
        loop {
            let dir = format!("/sys/fs/cgroup{path}");
            if let Some(max) = number(read(&format!("{dir}/memory.max"))) {
                let current = number(read(&format!("{dir}/memory.current"))).unwrap_or(0);
                let inactive = stat(&format!("{dir}/memory.stat"), "inactive_file");
                let here = left(max, current, inactive);
                least = Some(least.map_or(here, |l| l.min(here)));
            }
            match path.rfind('/') {
                Some(cut) if !path.is_empty() => path.truncate(cut),
                _ => break,
            }
        }
        if least.is_some() {
            return least;
        }
    }
    // v1: the memory controller's line, `N:memory:/path` (or with other controllers).
    let own = groups.lines().find_map(|l| {
        let mut parts = l.splitn(3, ':');
        let (_, controllers, path) = (parts.next()?, parts.next()?, parts.next()?);
        controllers
            .split(',')
            .any(|c| c == "memory")
            .then(|| path.trim_end_matches('/').to_string())
    });
    let dirs = own
        .map(|p| format!("/sys/fs/cgroup/memory{p}"))
        .into_iter()
        .chain(["/sys/fs/cgroup/memory".to_string()]);
    for dir in dirs {
        let Some(limit) = number(read(&format!("{dir}/memory.limit_in_bytes"))) else {
            continue;
        };
        // v1 writes a page-rounded i64::MAX when there is no limit.
        if limit >= 1 << 60 {
            return None;
        }
        let usage = number(read(&format!("{dir}/memory.usage_in_bytes"))).unwrap_or(0);
        let inactive = stat(&format!("{dir}/memory.stat"), "total_inactive_file");
        return Some(left(limit, usage, inactive));
    }
    None
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
    fn a_control_groups_limit_less_its_usage_less_reclaimable_cache() {
        use std::collections::HashMap;
        let with = |files: &[(&str, &str)]| {
            let files: HashMap<String, String> = files
                .iter()
                .map(|(p, t)| ((*p).to_string(), (*t).to_string()))
                .collect();
            cgroup_memory_left(&move |path: &str| files.get(path).cloned())
        };
        // v2: a limit of 1 000 000, 400 000 in use of which 150 000 inactive page cache.
        let v2 = [
            ("/proc/self/cgroup", "0::/box\n"),
            ("/sys/fs/cgroup/box/memory.max", "1000000\n"),
            ("/sys/fs/cgroup/box/memory.current", "400000\n"),
            (
                "/sys/fs/cgroup/box/memory.stat",
                "anon 200000\nfile 200000\ninactive_file 150000\nactive_file 50000\n",
            ),
        ];
        assert_eq!(with(&v2), Some(750_000));
        let mut unlimited = v2;
        unlimited[1].1 = "max\n";
        assert_eq!(with(&unlimited), None);
        // In a container's namespace the group is the root.
        let root = [
            ("/proc/self/cgroup", "0::/\n"),
            ("/sys/fs/cgroup/memory.max", "2000000\n"),
            ("/sys/fs/cgroup/memory.current", "500000\n"),
        ];
        assert_eq!(with(&root), Some(1_500_000));
        // A parent's lower limit binds the child (a job's step inside the job's group):
        // the least left of the two; a parent without a limit changes nothing.
        let nested = [
            ("/proc/self/cgroup", "0::/job/step\n"),
            ("/sys/fs/cgroup/job/step/memory.max", "max\n"),
            ("/sys/fs/cgroup/job/step/memory.current", "100000\n"),
            ("/sys/fs/cgroup/job/memory.max", "600000\n"),
            ("/sys/fs/cgroup/job/memory.current", "350000\n"),
        ];
        assert_eq!(with(&nested), Some(250_000));
        let mut child_lower = nested;
        child_lower[1].1 = "200000\n";
        assert_eq!(with(&child_lower), Some(100_000));
        let mut parent_unlimited = nested;
        parent_unlimited[3].1 = "max\n";
        assert_eq!(with(&parent_unlimited), None);
        // v1: the memory controller's own group, with other controllers on its line.
        let v1 = [
            ("/proc/self/cgroup", "5:cpu,cpuacct:/a\n4:memory:/job/7\n"),
            (
                "/sys/fs/cgroup/memory/job/7/memory.limit_in_bytes",
                "2000000",
            ),
            (
                "/sys/fs/cgroup/memory/job/7/memory.usage_in_bytes",
                "900000",
            ),
            (
                "/sys/fs/cgroup/memory/job/7/memory.stat",
                "cache 800000\ntotal_inactive_file 400000\n",
            ),
        ];
        assert_eq!(with(&v1), Some(1_500_000));
        // A group that is not mounted where its path says (a container): the root's.
        let mounted_at_root = [
            ("/proc/self/cgroup", "4:memory,hugetlb:/docker/abc\n"),
            ("/sys/fs/cgroup/memory/memory.limit_in_bytes", "1000000"),
            ("/sys/fs/cgroup/memory/memory.usage_in_bytes", "250000"),
        ];
        assert_eq!(with(&mounted_at_root), Some(750_000));
        let no_limit = [
            ("/proc/self/cgroup", "4:memory:/\n"),
            (
                "/sys/fs/cgroup/memory/memory.limit_in_bytes",
                "9223372036854771712",
            ),
        ];
        assert_eq!(with(&no_limit), None);
        assert_eq!(with(&[]), None);
    }
}
