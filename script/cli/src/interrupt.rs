//! Ctrl-C and SIGTERM for the commands that run recipes (every one but the REPL, which stops an
//! entry and keeps the session). The first signal sets the run's interrupt flag: the evaluation
//! and the kernel work it started stop at their next check, and a save under way stops and
//! removes its temporary file, leaving the old file as it was. A second signal, or the process
//! still running two seconds later (a studio serving its page), removes every temporary file
//! still listed (`blocksmith_kernel::io::remove_temporaries`) and exits with status 130.

use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::Duration;

/// Exit status after a signal: 128 + SIGINT, as shells report it.
const STOPPED: i32 = 130;

/// The process's interrupt flag, shared by every run the command starts.
#[must_use]
pub fn flag() -> Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    Arc::clone(FLAG.get_or_init(|| Arc::new(AtomicBool::new(false))))
}

/// Installs the handler described above. Without a handler (a system refusing one) the
/// signal ends the process as it would have.
pub fn install() {
    static SIGNALS: AtomicU32 = AtomicU32::new(0);
    let flag = flag();
    let _ = ctrlc::set_handler(move || {
        if SIGNALS.fetch_add(1, Ordering::SeqCst) > 0 {
            stop_now();
        }
        flag.store(true, Ordering::SeqCst);
        std::thread::spawn(|| {
            std::thread::sleep(Duration::from_secs(2));
            stop_now();
        });
    });
}

fn stop_now() -> ! {
    blocksmith_kernel::io::remove_temporaries();
    eprintln!("stopped");
    std::process::exit(STOPPED);
}
