//! A run stopped from outside while it writes its output leaves nothing:
//! not the output (it is renamed into place only when whole) and not the
//! temporary file it was writing, and it exits 130.

#![cfg(target_os = "linux")]

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The entries of `dir`.
fn entries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn a_run_stopped_while_writing_removes_its_unfinished_output_and_exits_130() {
    for signal in [libc::SIGTERM, libc::SIGINT] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("layers.json");
        // A million levels of the unit cube: seconds of writing, several
        // hundred MB if it ran to the end.
        let mut child = Command::new(env!("CARGO_BIN_EXE_wmslice"))
            .args(["slice", "unit_cube", "--layer-height", "1e-6", "--quiet"])
            .args(["--format", "json", "-o"])
            .arg(&out)
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Wait until the temporary file is there and growing.
        let start = Instant::now();
        let partial = loop {
            let found = entries(dir.path());
            if let Some(p) = found.iter().find(|n| n.ends_with(".partial")) {
                let p = dir.path().join(p);
                if std::fs::metadata(&p).map(|m| m.len() > 0).unwrap_or(false) {
                    break p;
                }
            }
            assert!(
                child.try_wait().unwrap().is_none(),
                "the run ended before it was stopped: {found:?}"
            );
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "no output started"
            );
            std::thread::sleep(Duration::from_millis(2));
        };
        let name = partial.file_name().unwrap().to_string_lossy().into_owned();
        assert!(name.starts_with(".layers.json."), "{name}");
        // SAFETY: `kill` on the id of a child this test started and has not
        // reaped.
        assert_eq!(unsafe { libc::kill(child.id() as i32, signal) }, 0);
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(130), "signal {signal}: {err}");
        assert!(
            err.contains("interrupted: the unfinished output was removed (1 file(s))"),
            "{err}"
        );
        assert_eq!(entries(dir.path()), Vec::<String>::new(), "signal {signal}");
    }
}
