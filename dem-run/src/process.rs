//! This machine and its processes, as run locks and case claims need them: the host name, and
//! whether a process of this host still runs (one implementation for both: `dem`'s run lock
//! and `dem sweep`'s claims had one each, and the claims' counted a zombie as running).

/// This machine's host name (`$HOSTNAME`, else `unknown-host`, if it cannot be read).
pub fn host() -> String {
    #[cfg(unix)]
    {
        let mut buf = [0u8; 256];
        // SAFETY: the buffer is valid for its length; gethostname writes at most that many
        // bytes (NUL-terminated or truncated), and we stop at the first NUL or the end.
        let r = unsafe { libc::gethostname(buf.as_mut_ptr().cast(), buf.len()) };
        if r == 0 {
            let end = buf.iter().position(|&b| b == 0).unwrap_or(buf.len());
            let name = String::from_utf8_lossy(&buf[..end]).trim().to_string();
            if !name.is_empty() {
                return name;
            }
        }
    }
    std::env::var("HOSTNAME")
        .ok()
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "unknown-host".into())
}

/// Whether process `pid` of this host exists and has not ended: `kill(pid, 0)` succeeds (or
/// is refused for permission: it exists), and it is not a zombie. A killed run whose parent
/// died too stays a zombie until init reaps it (a `dem sweep` runner killed with its case): it
/// exists, but runs no more. Without Unix, every process is taken to be alive.
pub fn alive(pid: u32) -> bool {
    #[cfg(unix)]
    {
        let Ok(p) = libc::pid_t::try_from(pid) else {
            return false;
        };
        // SAFETY: signal 0 sends nothing; it only checks that the process exists.
        if unsafe { libc::kill(p, 0) } == 0 {
            return !zombie(pid);
        }
        std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        true
    }
}

/// Whether process `pid` has ended but not been reaped (state `Z` or `X` in
/// `/proc/<pid>/stat`; false where there is no /proc).
pub fn zombie(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .ok()
        .and_then(|s| {
            // `pid (comm) state ...`: the command may hold spaces and parentheses.
            let rest = &s[s.rfind(')')? + 1..];
            rest.split_whitespace()
                .next()
                .map(|st| st == "Z" || st == "X")
        })
        .unwrap_or(false)
}

/// CPU time (s) the calling thread has used so far: Linux's `/proc/thread-self/schedstat`
/// (first field, ns); `None` elsewhere or if it cannot be read. An in-process case's cost.
pub fn thread_cpu_s() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn this_process_and_init_run_a_reaped_one_does_not() {
        assert!(alive(std::process::id()) && !zombie(std::process::id()));
        assert!(alive(1), "init runs");
        assert!(!host().is_empty());
        let mut c = std::process::Command::new("true").spawn().unwrap();
        let pid = c.id();
        c.wait().unwrap();
        assert!(!alive(pid), "an ended, reaped child is gone");
    }
}
