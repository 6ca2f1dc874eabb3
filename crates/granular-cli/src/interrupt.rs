//! Ctrl-C (SIGINT) and SIGTERM (a cluster scheduler at the end of a job's time) during
//! `granular run` and `resume`: the handler only records the signal; the run loop checks it
//! between chunks of events, writes a final checkpoint and stops
//! ([`granular::RunError::Interrupted`]); the command then exits with 128 + the signal's
//! number (130, 143). A second signal while the first is handled ends the process at once.

use signal_hook::consts::{SIGINT, SIGTERM};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The signal received, if any; the handlers are removed on drop (the Python package runs
/// the command line inside the interpreter, whose own handlers then work as before).
pub struct Interrupt {
    signal: Arc<AtomicUsize>,
    handlers: Vec<signal_hook::SigId>,
}

impl Interrupt {
    /// Installs the handlers of SIGINT and SIGTERM. Where they cannot be installed the
    /// signals keep their default action (the run ends without a final checkpoint).
    pub fn install() -> Interrupt {
        let signal = Arc::new(AtomicUsize::new(0));
        let armed = Arc::new(AtomicBool::new(false));
        let mut handlers = Vec::new();
        for sig in [SIGINT, SIGTERM] {
            // The shutdown first: on the first signal `armed` is still false.
            handlers.extend(
                [
                    signal_hook::flag::register_conditional_shutdown(
                        sig,
                        128 + sig,
                        Arc::clone(&armed),
                    ),
                    signal_hook::flag::register_usize(sig, Arc::clone(&signal), sig as usize),
                    signal_hook::flag::register(sig, Arc::clone(&armed)),
                ]
                .into_iter()
                .flatten(),
            );
        }
        Interrupt { signal, handlers }
    }

    /// The signal's number, once one arrived.
    pub fn received(&self) -> Option<i32> {
        match self.signal.load(Ordering::SeqCst) {
            0 => None,
            s => i32::try_from(s).ok(),
        }
    }

    /// The exit status of a run interrupted by the signal received: 128 + its number
    /// (130 for SIGINT, 143 for SIGTERM).
    pub fn exit_status(&self) -> u8 {
        self.received()
            .and_then(|s| u8::try_from(128 + s).ok())
            .unwrap_or(130)
    }

    /// A check for [`granular::Run::interrupt_when`].
    pub fn check(&self) -> impl FnMut() -> bool + Send + 'static {
        let signal = Arc::clone(&self.signal);
        move || signal.load(Ordering::SeqCst) != 0
    }
}

impl Drop for Interrupt {
    fn drop(&mut self) {
        for id in self.handlers.drain(..) {
            signal_hook::low_level::unregister(id);
        }
    }
}
