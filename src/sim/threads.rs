//! The thread pool a world steps on.
//!
//! The stages of `World::step` use rayon's current pool: run the steps
//! inside [`ThreadPool::install`] of a pool from [`thread_pool`] to choose
//! the number of threads (outside any pool, rayon's global pool uses every
//! core). The result is bit-identical for any number of threads, so the
//! count changes only the speed. A local pool, not the global one, lets one
//! process compare thread counts.

pub use rayon::ThreadPool;

/// Most threads accepted.
pub(crate) const MAX_THREADS: usize = 256;

/// The number of threads rayon uses when none is chosen: every core.
pub(crate) fn available_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The threads a pool has when none are asked for: one per core.
pub(crate) fn default_threads() -> usize {
    available_threads().min(MAX_THREADS)
}

/// A pool of `threads` workers (`None`: one per core).
pub fn thread_pool(threads: Option<usize>) -> Result<ThreadPool, String> {
    let threads = threads.unwrap_or_else(default_threads);
    if !(1..=MAX_THREADS).contains(&threads) {
        return Err(format!(
            "the number of threads must be between 1 and {MAX_THREADS}, got {threads}"
        ));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("lerpit-sim-{i}"))
        .build()
        .map_err(|e| format!("cannot start {threads} threads: {e}"))
}

/// A stage's parallel work is cut into about this many batches, between
/// which the step may give way.
const BATCHES: usize = 8;

/// How many of a stage's `tasks` go in one batch: about an eighth of
/// them, and at least `min` (enough work to be worth cutting).
pub(crate) fn batch_len(tasks: usize, min: usize) -> usize {
    tasks.div_ceil(BATCHES).max(min).max(1)
}

/// Run `tasks` in batches of `len`, in order, each batch by `run`; `None`
/// when `give_way` stopped them before a batch.
pub(crate) fn each_batch<T>(
    tasks: impl IntoIterator<Item = T>,
    len: usize,
    give_way: &mut GiveWay,
    mut run: impl FnMut(Vec<T>),
) -> Option<()> {
    let mut tasks = tasks.into_iter();
    loop {
        let batch: Vec<T> = tasks.by_ref().take(len.max(1)).collect();
        if batch.is_empty() {
            return Some(());
        }
        if give_way.stop() {
            return None;
        }
        run(batch);
    }
}

/// Where a stage run in batches may stop: `interrupted` is asked before
/// every batch but the stage's first.
pub(crate) struct GiveWay<'a> {
    interrupted: &'a dyn Fn() -> bool,
    started: bool,
}

impl<'a> GiveWay<'a> {
    pub(crate) fn new(interrupted: &'a dyn Fn() -> bool) -> Self {
        Self {
            interrupted,
            started: false,
        }
    }

    /// For a stage that nothing interrupts.
    pub(crate) fn never() -> GiveWay<'static> {
        static NEVER: fn() -> bool = || false;
        GiveWay::new(&NEVER)
    }

    /// Before a batch: whether the stage must stop here.
    pub(crate) fn stop(&mut self) -> bool {
        std::mem::replace(&mut self.started, true) && (self.interrupted)()
    }
}
