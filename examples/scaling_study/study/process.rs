//! One timed child process: whole-process wall time, exit status and peak resident memory.
//!
//! On Unix the child is reaped with `wait4`, which returns its own resource usage (`ru_maxrss`,
//! the peak resident set size, the same figure as `/usr/bin/time -v`), so the parent measures
//! memory without sampling and without a shell in between. Elsewhere the peak is unknown.

use std::fs::File;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How a child ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Exit {
    Code(i32),
    Signal(i32),
    TimedOut,
}

impl Exit {
    pub fn success(&self) -> bool {
        *self == Exit::Code(0)
    }
    pub fn describe(&self) -> String {
        match self {
            Exit::Code(c) => format!("exit {c}"),
            Exit::Signal(s) => format!("signal {s}"),
            Exit::TimedOut => "timed out".into(),
        }
    }
}

#[derive(Debug, Clone)]
pub struct Timed {
    /// From just before the spawn to the reaping of the child.
    pub wall: Duration,
    pub exit: Exit,
    /// Peak resident set size of the child (bytes), if the platform reports it.
    pub peak_rss: Option<u64>,
}

/// Run `cmd` in `cwd` (or the current folder) with stdin closed and stdout, stderr written to
/// the given files; kill it after `timeout`.
pub fn run_timed(
    cmd: &mut Command,
    cwd: Option<&Path>,
    stdout: &Path,
    stderr: &Path,
    timeout: Duration,
) -> std::io::Result<Timed> {
    if let Some(d) = cwd {
        cmd.current_dir(d);
    }
    cmd.stdin(Stdio::null())
        .stdout(File::create(stdout)?)
        .stderr(File::create(stderr)?);
    let start = Instant::now();
    let child = cmd.spawn()?;
    wait(child, start, timeout)
}

#[cfg(unix)]
fn wait(child: std::process::Child, start: Instant, timeout: Duration) -> std::io::Result<Timed> {
    use std::sync::mpsc;
    let pid = child.id() as libc::pid_t;
    let (tx, rx) = mpsc::channel();
    // The child is reaped here and only here (std's `Child` is never waited on), so its pid
    // stays valid for `kill` until this thread returns.
    let waiter = std::thread::spawn(move || {
        let mut status: libc::c_int = 0;
        // SAFETY: an all-zero `rusage` is a valid value; wait4 fills it.
        let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
        let r = loop {
            // SAFETY: valid pointers to a local status and rusage; pid is our unreaped child.
            let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
            if r == -1 && std::io::Error::last_os_error().kind() == std::io::ErrorKind::Interrupted
            {
                continue;
            }
            break r;
        };
        let wall = start.elapsed();
        let _ = tx.send(());
        if r == -1 {
            return Err(std::io::Error::last_os_error());
        }
        Ok((wall, status, usage.ru_maxrss))
    });
    let timed_out = rx.recv_timeout(timeout).is_err();
    if timed_out {
        // SAFETY: plain kill(2) of our own child, not yet reaped.
        unsafe {
            libc::kill(pid, libc::SIGKILL);
        }
    }
    let (wall, status, maxrss) = waiter.join().expect("wait thread")?;
    drop(child);
    let exit = if timed_out {
        Exit::TimedOut
    } else if libc::WIFEXITED(status) {
        Exit::Code(libc::WEXITSTATUS(status))
    } else if libc::WIFSIGNALED(status) {
        Exit::Signal(libc::WTERMSIG(status))
    } else {
        Exit::Code(-1)
    };
    // ru_maxrss is in KiB on Linux and the BSDs, in bytes on macOS.
    let unit: u64 = if cfg!(target_os = "macos") { 1 } else { 1024 };
    Ok(Timed {
        wall,
        exit,
        peak_rss: (maxrss > 0).then(|| maxrss as u64 * unit),
    })
}

#[cfg(not(unix))]
fn wait(
    mut child: std::process::Child,
    start: Instant,
    timeout: Duration,
) -> std::io::Result<Timed> {
    loop {
        if let Some(s) = child.try_wait()? {
            return Ok(Timed {
                wall: start.elapsed(),
                exit: Exit::Code(s.code().unwrap_or(-1)),
                peak_rss: None,
            });
        }
        if start.elapsed() > timeout {
            child.kill()?;
            child.wait()?;
            return Ok(Timed {
                wall: start.elapsed(),
                exit: Exit::TimedOut,
                peak_rss: None,
            });
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}
