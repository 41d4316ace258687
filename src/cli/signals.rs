//! SIGINT, SIGTERM and SIGHUP end the process as they always do, except while a run's
//! results are being swapped into its folder: there they wait until the swap is done, so
//! that an interrupted run leaves either the previous results or its own complete ones,
//! never a mix (the swap is a few renames, so the wait is milliseconds).
//!
//! Outside the swap the signal's default action is taken at once: a run interrupted while
//! it computes or writes into its staging folder leaves the previous results as they were
//! (its staging folder and lock file, both hidden, are removed by the next run there).
//! Elsewhere than on Unix nothing is installed.

/// Installs the handler (Unix; once, at the start of the process).
pub fn install() {
    #[cfg(unix)]
    unix::install();
}

/// Runs `f` with SIGINT, SIGTERM and SIGHUP held back; one that came meanwhile then ends
/// the process as it would have (the default action, so the exit status says which).
pub fn deferred<T>(f: impl FnOnce() -> T) -> T {
    #[cfg(unix)]
    {
        unix::deferred(f)
    }
    #[cfg(not(unix))]
    {
        f()
    }
}

#[cfg(unix)]
mod unix {
    use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

    /// The signals held back during a swap.
    const SIGNALS: [libc::c_int; 3] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP];

    /// True while a swap runs.
    static HOLDING: AtomicBool = AtomicBool::new(false);
    /// The signal that came while holding (0: none).
    static PENDING: AtomicI32 = AtomicI32::new(0);

    /// The handler: records the signal while holding, else takes its default action. Only
    /// atomics, `signal` and `raise`, which are async-signal-safe.
    extern "C" fn on_signal(signal: libc::c_int) {
        if HOLDING.load(Ordering::SeqCst) {
            PENDING.store(signal, Ordering::SeqCst);
        } else {
            take_default(signal);
        }
    }

    /// Restores the default action of `signal` and raises it: the process ends by it.
    fn take_default(signal: libc::c_int) {
        // SAFETY: `signal` and `raise` are async-signal-safe, and the arguments are a
        // valid signal number and the default disposition.
        unsafe {
            libc::signal(signal, libc::SIG_DFL);
            libc::raise(signal);
        }
    }

    pub fn install() {
        let handler = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
        for signal in SIGNALS {
            // SAFETY: installs a handler that only touches atomics and async-signal-safe
            // calls. A signal the parent set to be ignored (`nohup`) stays ignored.
            unsafe {
                if libc::signal(signal, handler) == libc::SIG_IGN {
                    libc::signal(signal, libc::SIG_IGN);
                }
            }
        }
    }

    pub fn deferred<T>(f: impl FnOnce() -> T) -> T {
        HOLDING.store(true, Ordering::SeqCst);
        let value = f();
        HOLDING.store(false, Ordering::SeqCst);
        match PENDING.swap(0, Ordering::SeqCst) {
            0 => value,
            signal => {
                take_default(signal);
                value
            }
        }
    }
}
