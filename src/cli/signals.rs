//! Termination signals as a request to stop: SIGINT (Ctrl-C), SIGTERM and SIGHUP. Once
//! [`catch`] has run, the first only sets a flag (and records which signal it was); the
//! commands that write images poll the flag, stop rendering, leave every file old or whole,
//! and exit with 128 + the signal's number, the shell's convention for a process a signal
//! ended. A second signal ends the process at once with 128 + its number, as an uncaught one
//! would: a run blocked where nothing polls the flag (reading a pipe that no one writes)
//! is stopped by Ctrl-C pressed twice. After [`catch_first_only`] (`figures`, whose sets
//! must each stay wholly old or wholly new) every signal is only a request.

use std::sync::Once;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The signals caught.
#[cfg(unix)]
const CAUGHT: [i32; 3] = [
    signal_hook::consts::SIGINT,
    signal_hook::consts::SIGTERM,
    signal_hook::consts::SIGHUP,
];
#[cfg(not(unix))]
const CAUGHT: [i32; 2] = [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM];

/// Set by any caught signal.
static STOP: AtomicBool = AtomicBool::new(false);
/// Whether a second signal is only a request too ([`catch_first_only`]).
static FIRST_ONLY: AtomicBool = AtomicBool::new(false);
/// The number of the last caught signal (0: none yet).
static LAST: AtomicUsize = AtomicUsize::new(0);

/// A signal that asked the program to stop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Signal(pub i32);

impl Signal {
    pub const INT: Signal = Signal(signal_hook::consts::SIGINT);

    /// `SIGINT`, `SIGTERM`, `SIGHUP`, or `signal N` for any other.
    pub fn name(self) -> String {
        match self.0 {
            signal_hook::consts::SIGINT => "SIGINT".into(),
            signal_hook::consts::SIGTERM => "SIGTERM".into(),
            #[cfg(unix)]
            signal_hook::consts::SIGHUP => "SIGHUP".into(),
            n => format!("signal {n}"),
        }
    }

    /// 128 + the signal's number: 130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP.
    pub fn exit_code(self) -> u8 {
        u8::try_from(128 + self.0).unwrap_or(u8::MAX)
    }

    /// How an error message says the program was stopped: Ctrl-C is a plain "interrupted",
    /// any other signal is named.
    pub fn interrupted(self) -> String {
        if self == Signal::INT {
            "interrupted".into()
        } else {
            format!("interrupted by {}", self.name())
        }
    }
}

/// Makes the first caught signal set the returned flag instead of ending the process, and a
/// second one end it (once per process). A signal for which no handler can be installed
/// keeps its default action, which ends the process, as the second does: every file is then
/// old or whole, only a temporary file may be left if it lands while one is written.
pub fn catch() -> &'static AtomicBool {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        for signal in CAUGHT {
            // Handlers run in the order registered: the first sees the flag as the signals
            // before this one left it. Then the number, before the flag: whoever sees the
            // flag set finds it recorded.
            let code = i32::from(Signal(signal).exit_code());
            let second_ends = move || {
                if STOP.load(Ordering::SeqCst) && !FIRST_ONLY.load(Ordering::SeqCst) {
                    signal_hook::low_level::exit(code);
                }
            };
            // SAFETY: the action only loads two atomics and calls `_exit`, both
            // async-signal-safe.
            let _ = unsafe { signal_hook::low_level::register(signal, second_ends) };
            let _ = signal_hook::flag::register_usize(signal, &LAST, signal as usize);
            let _ = signal_hook::flag::register(signal, &STOP);
        }
    });
    &STOP
}

/// [`catch`], with every signal, the second too, only a request to stop.
pub fn catch_first_only() -> &'static AtomicBool {
    FIRST_ONLY.store(true, Ordering::SeqCst);
    catch()
}

/// The signal that asked the program to stop, if one did.
pub fn received() -> Option<Signal> {
    if !STOP.load(Ordering::SeqCst) {
        return None;
    }
    match LAST.load(Ordering::SeqCst) {
        0 => Some(Signal::INT),
        n => Some(Signal(n as i32)),
    }
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::process::{Command, ExitStatus, Stdio};

    /// Set in the copy of this test binary that [`alone`] starts.
    const ALONE: &str = "LUMIERE_SIGNAL_TEST_ALONE";

    /// Runs test `name` of this module alone, in a new process of this test binary (signals
    /// and the flags they set are the whole process's), and returns how that process ended.
    fn alone(name: &str) -> ExitStatus {
        let path = format!("cli::signals::tests::{name}");
        Command::new(std::env::current_exe().unwrap())
            .args([path.as_str(), "--exact", "--test-threads=1"])
            .env(ALONE, "1")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .unwrap()
    }

    fn raise(signal: i32) {
        // SAFETY: sends a signal to this thread; the handlers `catch` installs only store
        // to atomics or call `_exit`.
        assert_eq!(unsafe { libc::raise(signal) }, 0);
    }

    #[test]
    fn after_catch_a_second_signal_ends_the_process() {
        if std::env::var_os(ALONE).is_none() {
            // 130: ended by the second SIGINT, after the first was only recorded (a process
            // that survives both passes its test and exits 0).
            assert_eq!(alone("after_catch_a_second_signal_ends_the_process").code(), Some(130));
            return;
        }
        let stop = catch();
        raise(libc::SIGINT);
        assert!(stop.load(Ordering::SeqCst));
        assert_eq!(received(), Some(Signal::INT));
        raise(libc::SIGINT);
    }

    #[test]
    fn after_catch_first_only_every_signal_is_a_request() {
        if std::env::var_os(ALONE).is_none() {
            // 0: the process survived three signals and its assertions held.
            assert_eq!(
                alone("after_catch_first_only_every_signal_is_a_request").code(),
                Some(0)
            );
            return;
        }
        let stop = catch_first_only();
        raise(libc::SIGINT);
        raise(libc::SIGTERM);
        raise(libc::SIGINT);
        assert!(stop.load(Ordering::SeqCst));
        assert_eq!(received(), Some(Signal::INT));
    }

    #[test]
    fn exit_codes_and_names() {
        assert_eq!(Signal(libc::SIGINT).exit_code(), 130);
        assert_eq!(Signal(libc::SIGHUP).exit_code(), 129);
        assert_eq!(Signal(libc::SIGTERM).exit_code(), 143);
        assert_eq!(Signal(libc::SIGINT).interrupted(), "interrupted");
        assert_eq!(Signal(libc::SIGTERM).interrupted(), "interrupted by SIGTERM");
        assert_eq!(Signal(libc::SIGHUP).interrupted(), "interrupted by SIGHUP");
        assert_eq!(Signal(200).exit_code(), 255);
    }
}
