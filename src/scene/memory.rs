//! What the first step of a built scene will hold in memory, against what
//! the system has: a scene whose overlapping pairs cannot be held is
//! refused before it runs, not aborted by the allocator part-way. And a
//! reader told of an allocation that fails ([`Recoverable`]), where the
//! program's allocator (`cli::out_of_memory`) would otherwise end it.

use crate::sim::Contact;
use std::cell::Cell;

/// Bytes a sphere takes besides its contacts: the bodies, the grid and the
/// buffers (peak resident memory of the benchmark's dilute start: 151 to
/// 200 bytes a sphere from N = 10^5 up; of its settled start, keeping no
/// list of contacts, 181 to 243: `lerpit bench --start S --particles N`
/// at 10^5 and 10^6, `peak_rss_bytes_per_sphere`).
pub(crate) const BYTES_PER_SPHERE: f64 = 256.0;

/// Memory this process can still take, and what limits it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Available {
    pub bytes: u64,
    /// What sets the figure, for messages: free memory, or a limit.
    pub what: &'static str,
    /// Under an address-space limit: what the threads may reserve,
    /// withheld from `bytes`, and the room before it was.
    pub reserved: Option<(Reserved, u64)>,
}

/// Address space threads may reserve besides what they allocate, which
/// only an address-space limit (`ulimit -v`) counts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Reserved {
    pub threads: usize,
    /// Their stacks not yet mapped (2 MiB each, Rust's default; none once
    /// the threads run).
    pub stacks: u64,
    /// With glibc, a range for the allocations of each of up to eight
    /// threads a core ([`ARENA_BYTES`]), reserved when a thread first
    /// allocates. Without it, `bench --threads 64` under `ulimit -v
    /// 2000000` passed the check and then aborted.
    pub arenas: u64,
}

impl Reserved {
    fn of(threads: usize, running: bool) -> Self {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let arenas = if ONE_ARENA.load(std::sync::atomic::Ordering::Relaxed) {
            0
        } else {
            threads.min(8 * cores) as u64
        };
        Self {
            threads,
            stacks: if running {
                0
            } else {
                threads as u64 * (2 << 20)
            },
            arenas: arenas * ARENA_BYTES,
        }
    }

    fn total(self) -> u64 {
        self.stacks + self.arenas
    }
}

/// The range glibc reserves for a thread's allocations, bytes.
const ARENA_BYTES: u64 = 64 << 20;

/// [`one_arena_under_a_limit`] asked glibc for one range for all threads.
static ONE_ARENA: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Under an address-space limit (`ulimit -v`), have every thread allocate
/// from glibc's one main range, before any thread starts. Each thread's
/// range of its own (64 MiB) is reserved as it first allocates, while
/// there is room, and the threads started after it then found none for
/// their stacks: `--threads 8` under `ulimit -v 150000` failed to start,
/// and 128 threads under 600 MB aborted. Sharing one range costs some
/// waiting on the allocator, only under such a limit.
pub(crate) fn one_arena_under_a_limit() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        let limited = std::fs::read_to_string("/proc/self/limits")
            .ok()
            .and_then(|l| soft_limit(&l, "Max address space"))
            .is_some();
        // SAFETY: mallopt only sets a parameter of the allocator; no
        // thread has started yet.
        if limited && unsafe { libc::mallopt(libc::M_ARENA_MAX, 1) } == 1 {
            ONE_ARENA.store(true, std::sync::atomic::Ordering::Relaxed);
        }
    }
}

impl std::fmt::Display for Available {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} are available ({}",
            memory_size(self.bytes as f64),
            self.what
        )?;
        // What the threads may reserve, where it is anything (their
        // stacks are mapped once they run, and one range serves all).
        if let Some((reserved, _)) = self.reserved.filter(|(r, _)| r.total() > 0) {
            let threads = match reserved.threads {
                1 => "the thread".to_string(),
                n => format!("the {n} threads"),
            };
            write!(
                f,
                ", less about {} that {threads} may reserve",
                memory_size(reserved.total() as f64)
            )?;
        }
        write!(f, ")")
    }
}

impl Available {
    /// Whether `need` bytes can be had: within `bytes`, or, smaller than
    /// a thread's allocation range, within the ranges withheld for the
    /// threads, from which glibc gives such allocations.
    pub(crate) fn fits(&self, need: f64) -> bool {
        let arenas = self.reserved.map_or(0, |(r, _)| r.arenas);
        need <= self.bytes as f64
            || (need < ARENA_BYTES as f64 && need <= (self.bytes + arenas) as f64)
    }

    /// The way out of needing `need` bytes, more than are available:
    /// `otherwise`, unless the threads' reservations are what leaves too
    /// little (`need` fits the limit without them).
    pub(crate) fn way_out(&self, need: f64, otherwise: &str) -> String {
        match self.reserved {
            Some((r, room)) if need <= room as f64 => {
                let one = Reserved::of(1, r.stacks == 0).total();
                if r.threads > 1 && need + one as f64 <= room as f64 {
                    "Run on fewer threads (--threads 1), or raise the limit".into()
                } else {
                    "Raise the limit".into()
                }
            }
            _ => otherwise.into(),
        }
    }
}

/// `bytes` for a message: in MB below a gigabyte, else in GB; under half
/// a megabyte, in kB or bytes (not "0 MB").
pub(crate) fn memory_size(bytes: f64) -> String {
    let mut text = String::new();
    write_memory_size(&mut text, bytes).expect("a String takes any text");
    text
}

/// [`memory_size`] written to `out`, which need not allocate (the
/// message of memory that ran out: `cli/out_of_memory.rs`).
pub(crate) fn write_memory_size(out: &mut impl std::fmt::Write, bytes: f64) -> std::fmt::Result {
    if bytes < 1e3 {
        write!(out, "{bytes:.0} bytes")
    } else if bytes < 0.5e6 {
        write!(out, "{:.0} kB", bytes / 1e3)
    } else if bytes < 1e9 {
        write!(out, "{:.0} MB", bytes / 1e6)
    } else {
        write!(out, "{:.1} GB", bytes / 1e9)
    }
}

/// Memory this process can still take without swapping or being stopped
/// by a limit (Linux): the least of the system's available memory
/// (MemAvailable), what the address-space and data limits (`ulimit -v`,
/// `ulimit -d`) leave above what the process already maps, and what its
/// control group's memory limit leaves. `None` where none can be read.
/// Called from the threads that will do the work (their stacks mapped).
pub(crate) fn available_memory() -> Option<Available> {
    available(Reserved::of(rayon::current_num_threads(), true))
}

/// [`available_memory`] for a process about to start `threads` threads:
/// under an address-space limit, less what they may reserve besides what
/// they allocate ([`Reserved`]).
pub(crate) fn available_memory_for(threads: usize) -> Option<Available> {
    available(Reserved::of(threads, false))
}

fn available(reserved: Reserved) -> Option<Available> {
    let kb = |text: &str, key: &str| -> Option<u64> {
        let line = text.lines().find(|l| l.starts_with(key))?;
        Some(line.split_whitespace().nth(1)?.parse::<u64>().ok()? * 1024)
    };
    let mut found = Vec::new();
    if let Ok(info) = std::fs::read_to_string("/proc/meminfo")
        && let Some(bytes) = kb(&info, "MemAvailable:")
    {
        found.push(Available {
            bytes,
            what: "the system's available memory",
            reserved: None,
        });
    }
    if let (Ok(limits), Ok(status)) = (
        std::fs::read_to_string("/proc/self/limits"),
        std::fs::read_to_string("/proc/self/status"),
    ) {
        for (limit, used, what) in [
            (
                "Max address space",
                "VmSize:",
                "the address-space limit, ulimit -v",
            ),
            ("Max data size", "VmData:", "the data-size limit, ulimit -d"),
        ] {
            let address_space = used == "VmSize:";
            if let (Some(max), Some(used)) = (soft_limit(&limits, limit), kb(&status, used)) {
                let room = max.saturating_sub(used);
                let reserved = address_space.then_some((reserved, room));
                found.push(Available {
                    bytes: room.saturating_sub(reserved.map_or(0, |(r, _)| r.total())),
                    what,
                    reserved,
                });
            }
        }
    }
    if let Some(bytes) = cgroup_room() {
        found.push(Available {
            bytes,
            what: "the control group's memory limit",
            reserved: None,
        });
    }
    found.into_iter().min_by_key(|a| a.bytes)
}

/// Refuse to start `threads` threads when an address-space limit leaves
/// too little for their stacks and [`LEAST_ROOM`] besides: a
/// message that names the threads, not the scene, which any size would
/// fail.
pub(crate) fn check_threads(threads: usize) -> Result<(), String> {
    let run = Beside {
        bytes: LEAST_ROOM,
        what: "the run".into(),
        choose: true,
    };
    check_threads_within(threads, available_memory_for(threads), &run)
}

/// [`check_threads`] for a command whose threads are one a core (with no
/// `--threads` to choose fewer) and that needs `bytes` (at least
/// [`LEAST_ROOM`]) besides their stacks for `what`.
pub(crate) fn check_core_threads(bytes: f64, what: &str) -> Result<(), String> {
    let threads = crate::sim::threads::default_threads();
    let beside = Beside {
        bytes: bytes.max(LEAST_ROOM),
        what: format!("{what} (about {})", memory_size(bytes.max(LEAST_ROOM))),
        choose: false,
    };
    check_threads_within(threads, available_memory_for(threads), &beside)
}

/// What a command needs besides its threads' stacks.
struct Beside {
    bytes: f64,
    /// For the message: "the run".
    what: String,
    /// Whether `--threads` can ask for fewer.
    choose: bool,
}

/// [`check_threads`] against `available` ([`available_memory_for`]).
fn check_threads_within(
    threads: usize,
    available: Option<Available>,
    beside: &Beside,
) -> Result<(), String> {
    let Some(available) = available else {
        return Ok(());
    };
    let Some((reserved, room)) = available.reserved else {
        return Ok(());
    };
    if room as f64 >= reserved.stacks as f64 + beside.bytes {
        return Ok(());
    }
    let one = Reserved::of(1, false).stacks as f64 + beside.bytes;
    let (stacks, fewer) = match threads {
        1 => ("the thread's stack".to_string(), ""),
        n if beside.choose && room as f64 >= one => (
            format!("{n} threads' stacks"),
            " or run on fewer threads (--threads 1)",
        ),
        n => (format!("{n} threads' stacks"), ""),
    };
    Err(format!(
        "the address-space limit (ulimit -v) leaves {} of memory, too little for {stacks} ({}) \
         and {}. Raise the limit{fewer}",
        memory_size(room as f64),
        memory_size(reserved.stacks as f64),
        beside.what,
    ))
}

/// Memory (bytes) [`check_threads`] leaves room for besides the stacks:
/// the collisions lesson ran with 8 MB left for it and 2 threads.
const LEAST_ROOM: f64 = 1e6;

/// The soft limit on the line of `/proc/self/limits` that starts with
/// `name`, bytes; `None` when unlimited or not there.
fn soft_limit(limits: &str, name: &str) -> Option<u64> {
    let line = limits.lines().find(|l| l.starts_with(name))?;
    line[name.len()..].split_whitespace().next()?.parse().ok()
}

/// The value of `key` in a cgroup `memory.stat` (`key value` lines).
fn stat_value(stat: &str, key: &str) -> Option<u64> {
    stat.lines().find_map(|l| {
        let (k, v) = l.split_once(' ')?;
        (k == key).then(|| v.trim().parse().ok()).flatten()
    })
}

/// Limits at or above this are "no limit" (cgroup v1 writes 2^63 rounded
/// down to a page).
const NO_LIMIT: u64 = 1 << 60;

/// What the memory limits of this process's control group and its parents
/// leave (cgroup v2 `memory.max` less `memory.current`, or v1
/// `memory.limit_in_bytes` less `memory.usage_in_bytes`), bytes; `None`
/// without a limit.
fn cgroup_room() -> Option<u64> {
    let groups = std::fs::read_to_string("/proc/self/cgroup").ok()?;
    let read = |path: std::path::PathBuf| -> Option<u64> {
        std::fs::read_to_string(path).ok()?.trim().parse().ok()
    };
    let mut room: Option<u64> = None;
    for line in groups.lines() {
        let mut parts = line.splitn(3, ':');
        let (_, controllers, path) = (parts.next()?, parts.next()?, parts.next()?);
        let (root, max, current, cache) = match controllers {
            "" => (
                "/sys/fs/cgroup",
                "memory.max",
                "memory.current",
                "inactive_file",
            ),
            c if c.split(',').any(|c| c == "memory") => (
                "/sys/fs/cgroup/memory",
                "memory.limit_in_bytes",
                "memory.usage_in_bytes",
                "total_inactive_file",
            ),
            _ => continue,
        };
        // The group and each parent up to the root: the least room counts.
        let mut dir = std::path::PathBuf::from(root).join(path.trim_start_matches('/'));
        loop {
            if let (Some(max), Some(current)) = (read(dir.join(max)), read(dir.join(current)))
                && max < NO_LIMIT
            {
                // Page cache the kernel gives back under pressure is not
                // in use (the "working set" container tools report).
                let reclaimable = std::fs::read_to_string(dir.join("memory.stat"))
                    .ok()
                    .and_then(|stat| stat_value(&stat, cache))
                    .unwrap_or(0);
                let left = max.saturating_sub(current.saturating_sub(reclaimable));
                room = Some(room.map_or(left, |r| r.min(left)));
            }
            if dir == std::path::Path::new(root) || !dir.pop() {
                break;
            }
        }
    }
    room
}

/// Memory the first step of `n` spheres with `pairs` overlapping pairs
/// needs, bytes: each sphere's share, and the contact list with the
/// quarter more room the grid leaves for the next step.
pub(crate) fn first_step_bytes(n: u64, pairs: u64) -> f64 {
    n as f64 * BYTES_PER_SPHERE + 1.25 * size_of::<Contact>() as f64 * pairs as f64
}

/// Refuse `n` spheres when what they take without any contact (a first
/// step with no overlapping pair) is more than is `available`: checked
/// before a scene places its spheres, so that placing them cannot run out.
pub(crate) fn check_spheres(n: u64, available: Option<Available>) -> Result<(), String> {
    let Some(available) = available else {
        return Ok(());
    };
    let need = first_step_bytes(n, 0);
    if available.fits(need) {
        return Ok(());
    }
    Err(format!(
        "the scene's {} {} about {} of memory, and {available}. {}",
        crate::scene::spheres(n as usize),
        if n == 1 { "needs" } else { "need" },
        memory_size(need),
        available.way_out(need, "Use fewer spheres"),
    ))
}

/// Refuse a first step that needs more than is `available` (`None`: not
/// known, nothing is refused), saying how much each is.
pub(crate) fn check_first_step(
    n: u64,
    pairs: u64,
    available: Option<Available>,
) -> Result<(), String> {
    let Some(available) = available else {
        return Ok(());
    };
    let need = first_step_bytes(n, pairs);
    if available.fits(need) {
        return Ok(());
    }
    Err(if pairs == 0 {
        format!(
            "the first step of {} needs about {} of memory, and {available}. {}",
            crate::scene::spheres(n as usize),
            memory_size(need),
            available.way_out(need, "Use fewer spheres"),
        )
    } else {
        format!(
            "the {} spheres start with {} overlapping pairs: the first step needs about \
             {} of memory to hold them, and {available}. {}",
            crate::scene::thousands(n),
            crate::scene::thousands(pairs),
            memory_size(need),
            available.way_out(need, "Use fewer spheres, or spread them out"),
        )
    })
}

thread_local! {
    /// Readers on this thread that are told of a failed allocation, now.
    static RECOVERABLE: Cell<usize> = const { Cell::new(0) };
}

/// While one is held, an allocation of its thread that fails is returned
/// to its caller (as null: `try_reserve` and `read_to_end` report it)
/// instead of ending the program. Hold it around the reading only: any
/// other allocation that fails meanwhile gets the null too, and Rust
/// aborts.
pub(crate) struct Recoverable(std::marker::PhantomData<*const ()>);

impl Recoverable {
    pub(crate) fn hold() -> Self {
        RECOVERABLE.with(|r| r.set(r.get() + 1));
        Self(std::marker::PhantomData)
    }
}

impl Drop for Recoverable {
    fn drop(&mut self) {
        RECOVERABLE.with(|r| r.set(r.get() - 1));
    }
}

/// Whether a reader of this thread is told of a failed allocation now:
/// read without allocating (a thread-local of `const` initial value and no
/// destructor), so the allocator may ask it as an allocation fails.
pub(crate) fn told_of_failure() -> bool {
    RECOVERABLE.try_with(Cell::get).unwrap_or(0) > 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spheres_that_cannot_be_held_are_refused_before_they_are_placed() {
        let limit = |bytes: u64| {
            Some(Available {
                bytes,
                what: "the address-space limit, ulimit -v",
                reserved: None,
            })
        };
        let need = 1_000_000.0 * BYTES_PER_SPHERE;
        assert_eq!(check_spheres(1_000_000, None), Ok(()));
        assert_eq!(check_spheres(1_000_000, limit(need as u64)), Ok(()));
        let refused = check_spheres(1_000_000, limit(need as u64 - 1)).unwrap_err();
        assert!(
            refused.contains("1,000,000 spheres need about 256 MB")
                && refused.contains("256 MB are available (the address-space limit, ulimit -v)"),
            "{refused}"
        );
    }

    #[test]
    fn a_first_step_that_cannot_be_held_is_refused_with_both_figures() {
        let need = first_step_bytes(1000, 64_000);
        assert!(need > 1000.0 * BYTES_PER_SPHERE);
        let free = |bytes: u64| {
            Some(Available {
                bytes,
                what: "the address-space limit, ulimit -v",
                reserved: None,
            })
        };
        assert_eq!(check_first_step(1000, 64_000, None), Ok(()));
        assert_eq!(
            check_first_step(1000, 64_000, free(need as u64 + 1)),
            Ok(())
        );
        let refused = check_first_step(1000, 64_000, free(need as u64 / 2)).unwrap_err();
        assert!(
            refused.contains("the 1,000 spheres start with 64,000 overlapping pairs")
                && refused.contains("MB of memory")
                && refused.contains("MB are available (the address-space limit, ulimit -v)"),
            "{refused}"
        );
        // Without overlaps (memory taken while placing them), no word of
        // spreading them out.
        let refused = check_first_step(1_000_000, 0, free(1000)).unwrap_err();
        assert!(
            refused.starts_with("the first step of 1,000,000 spheres needs about 256 MB")
                && !refused.contains("spread"),
            "{refused}"
        );
    }

    #[test]
    fn a_limit_that_the_threads_reservations_fill_says_so_and_not_fewer_spheres() {
        // Two threads to start: 4 MiB of stacks and two 64 MiB ranges
        // withheld from what an address-space limit leaves.
        let under = |room: u64| Available {
            bytes: room.saturating_sub(Reserved::of(2, false).total()),
            what: "the address-space limit, ulimit -v",
            reserved: Some((Reserved::of(2, false), room)),
        };
        // Sizes under a range come from the ranges: 100 MB leave room for
        // one sphere and for 100,000 (25.6 MB), though none is left
        // besides the ranges.
        assert_eq!(under(100_000_000).bytes, 0);
        assert_eq!(check_spheres(1, Some(under(100_000_000))), Ok(()));
        assert_eq!(check_spheres(100_000, Some(under(100_000_000))), Ok(()));
        // 300,000 (76.8 MB) fit the limit but not besides the ranges:
        // the threads are named, and one thread is the way out where it
        // would leave room.
        let refused = check_spheres(300_000, Some(under(100_000_000))).unwrap_err();
        assert!(
            refused.ends_with("less about 138 MB that the 2 threads may reserve). Raise the limit"),
            "{refused}"
        );
        let refused = check_spheres(300_000, Some(under(200_000_000))).unwrap_err();
        assert!(
            refused.ends_with("Run on fewer threads (--threads 1), or raise the limit"),
            "{refused}"
        );
        // A need beyond the limit even without them: fewer spheres.
        let refused = check_spheres(1_000_000, Some(under(200_000_000))).unwrap_err();
        assert!(refused.ends_with("Use fewer spheres"), "{refused}");
        // Threads that reserve nothing more (running, on one range) are
        // not named: "less about 0 bytes" read as a fault.
        let running = Reserved {
            threads: 2,
            stacks: 0,
            arenas: 0,
        };
        let said = Available {
            bytes: 1_000_000,
            what: "the address-space limit, ulimit -v",
            reserved: Some((running, 1_000_000)),
        }
        .to_string();
        assert_eq!(
            said,
            "1 MB are available (the address-space limit, ulimit -v)"
        );
        let run = Beside {
            bytes: LEAST_ROOM,
            what: "the run".into(),
            choose: true,
        };
        // Room for the stacks and a megabyte besides: the threads start.
        assert_eq!(
            check_threads_within(2, Some(under(6_000_000)), &run),
            Ok(())
        );
        assert_eq!(check_threads_within(2, None, &run), Ok(()));
        assert_eq!(
            check_threads_within(2, Some(under(5_000_000)), &run),
            Err(
                "the address-space limit (ulimit -v) leaves 5 MB of memory, too little for 2 \
                 threads' stacks (4 MB) and the run. Raise the limit or run on fewer threads \
                 (--threads 1)"
                    .into()
            )
        );
        assert_eq!(
            check_threads_within(2, Some(under(3_000_000)), &run),
            Err(
                "the address-space limit (ulimit -v) leaves 3 MB of memory, too little for 2 \
                 threads' stacks (4 MB) and the run. Raise the limit"
                    .into()
            )
        );
        // With no --threads to choose (the study's one a core), only the
        // limit is the way out, and what the study needs is said.
        let study = Beside {
            bytes: 3e6,
            what: "the study (about 3 MB)".into(),
            choose: false,
        };
        assert_eq!(
            check_threads_within(2, Some(under(6_000_000)), &study),
            Err(
                "the address-space limit (ulimit -v) leaves 6 MB of memory, too little for 2 \
                 threads' stacks (4 MB) and the study (about 3 MB). Raise the limit"
                    .into()
            )
        );
        assert_eq!(
            check_threads_within(2, Some(under(7_200_000)), &study),
            Ok(())
        );
    }

    #[test]
    fn limits_are_read_from_their_lines_and_unlimited_is_none() {
        let limits = "Limit                     Soft Limit           Hard Limit           Units\n\
                      Max data size             unlimited            unlimited            bytes\n\
                      Max address space         3072000000           unlimited            bytes\n";
        assert_eq!(soft_limit(limits, "Max address space"), Some(3_072_000_000));
        assert_eq!(soft_limit(limits, "Max data size"), None);
        assert_eq!(soft_limit(limits, "Max file locks"), None);
        let stat = "anon 100\nfile 900\ninactive_file 700\ntotal_inactive_file 5\n";
        assert_eq!(stat_value(stat, "inactive_file"), Some(700));
        assert_eq!(stat_value(stat, "total_inactive_file"), Some(5));
        assert_eq!(stat_value(stat, "active_file"), None);
        let small = Available {
            bytes: 40_000_000,
            what: "the control group's memory limit",
            reserved: None,
        };
        assert_eq!(
            small.to_string(),
            "40 MB are available (the control group's memory limit)"
        );
    }
}
