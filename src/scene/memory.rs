//! What the first step of a built scene will hold in memory, against what
//! the system has: a scene whose overlapping pairs cannot be held is
//! refused before it runs, not aborted by the allocator part-way.

use crate::sim::Contact;

/// Bytes a sphere takes besides its contacts: the bodies, the grid and the
/// buffers (peak resident memory of the benchmark's dilute start: 170 to
/// 210 bytes a sphere from N = 10^5 up).
pub(crate) const BYTES_PER_SPHERE: f64 = 256.0;

/// Memory the system can give without swapping, bytes (Linux:
/// MemAvailable); `None` where it cannot be read.
pub(crate) fn available_memory_bytes() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Memory the first step of `n` spheres with `pairs` overlapping pairs
/// needs, bytes: each sphere's share, and the contact list with the
/// quarter more room the grid leaves for the next step.
pub(crate) fn first_step_bytes(n: u64, pairs: u64) -> f64 {
    n as f64 * BYTES_PER_SPHERE + 1.25 * size_of::<Contact>() as f64 * pairs as f64
}

/// Refuse a first step that needs more than `available` bytes (`None`: not
/// known, nothing is refused), saying how much each is.
pub(crate) fn check_first_step(n: u64, pairs: u64, available: Option<u64>) -> Result<(), String> {
    let Some(available) = available else {
        return Ok(());
    };
    let need = first_step_bytes(n, pairs);
    if need <= available as f64 {
        return Ok(());
    }
    Err(format!(
        "the {n} spheres start with {pairs} overlapping pairs: the first step needs about \
         {:.1} GB of memory to hold them, and {:.1} GB are available. Use fewer spheres, \
         or spread them out",
        need / 1e9,
        available as f64 / 1e9
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_first_step_that_cannot_be_held_is_refused_with_both_figures() {
        let need = first_step_bytes(1000, 64_000);
        assert!(need > 1000.0 * BYTES_PER_SPHERE);
        assert_eq!(check_first_step(1000, 64_000, None), Ok(()));
        assert_eq!(
            check_first_step(1000, 64_000, Some(need as u64 + 1)),
            Ok(())
        );
        let refused = check_first_step(1000, 64_000, Some(need as u64 / 2)).unwrap_err();
        assert!(
            refused.contains("64000 overlapping pairs") && refused.contains("GB are available"),
            "{refused}"
        );
    }
}
