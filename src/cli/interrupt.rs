//! Ctrl-C (SIGINT) and SIGTERM during a long command: the render stops, its temporary output
//! file is removed, and the command exits with the shell's code for that signal (130 or 143)
//! after one line on stderr.
//!
//! Without this, the signal's default action kills the process on the spot, and the
//! temporary file that `PendingOutput` writes beside the output (to rename it into place only
//! when complete) stays behind. With it, the signal only raises the render's [`Cancel`] flag:
//! every tile job checks it before it starts, so the render returns within one tile's time,
//! the command returns an error, and dropping the pending output deletes its temporary file.
//! A second signal does not wait for the running tiles (a tile of a render with a huge `--spp`
//! can take minutes): it removes the temporary file itself and exits at once.
//! A part of the command line's layer: the renderer below knows only the flag.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicI32, Ordering};

use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::iterator::{Handle, Signals};

use crate::error::Error;
use crate::schedule::progressive::Cancel;

/// Watches for SIGINT and SIGTERM while it lives, cancelling `cancel` on the first one.
pub struct Interrupt {
    signal: Arc<AtomicI32>,
    handle: Handle,
}

impl Interrupt {
    /// Starts watching; the signals' default actions are suspended until it is dropped.
    /// `temp` is the file to remove if a second signal comes before the render has stopped.
    pub fn watch(cancel: Cancel, temp: PathBuf) -> Result<Interrupt, Error> {
        let mut signals =
            Signals::new([SIGINT, SIGTERM]).map_err(|e| Error::new(format!("cannot catch Ctrl-C: {e}")))?;
        let (handle, signal) = (signals.handle(), Arc::new(AtomicI32::new(0)));
        let caught = Arc::clone(&signal);
        std::thread::Builder::new()
            .name("raypool-signals".into())
            .spawn(move || {
                for number in signals.forever() {
                    if caught.swap(number, Ordering::SeqCst) != 0 {
                        let _ = std::fs::remove_file(&temp);
                        let error = Error::interrupted(number);
                        eprintln!("raypool: error: {error}");
                        std::process::exit(error.exit_code().into());
                    }
                    cancel.cancel();
                }
            })
            .map_err(|e| Error::new(format!("cannot start the signal thread: {e}")))?;
        Ok(Interrupt { signal, handle })
    }

    /// `Err` (exit 130 or 143) if a signal came.
    pub fn check(&self) -> Result<(), Error> {
        match self.signal.load(Ordering::SeqCst) {
            0 => Ok(()),
            number => Err(Error::interrupted(number)),
        }
    }
}

impl Drop for Interrupt {
    fn drop(&mut self) {
        self.handle.close(); // the thread's loop ends and the signals' handlers go
    }
}
