//! A signal during a run (Ctrl-C, or SIGTERM from a job scheduler) stops it without leaving a
//! half-written file or a temporary behind: the first signal stops the evaluation and the save
//! under way (which removes its temporary and keeps the old file), a second one exits at once.

use std::process::Command;
use std::time::Duration;

#[test]
fn sigterm_during_saves_leaves_whole_files_and_no_temporaries() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("saves.rhai");
    // Many large saves, so the signal lands in one (or between two) whenever it comes.
    std::fs::write(&recipe, "let m = icosphere(1, 7);\nfor i in 0..200 { m.save(`big${i}.stl`); }\nm\n").unwrap();
    for delay in [300, 900] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_blocksmith"))
            .arg("run")
            .arg(&recipe)
            .current_dir(dir.path())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(delay));
        let killed = Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap();
        assert!(killed.success());
        let status = child.wait().unwrap();
        assert!(!status.success(), "a stopped run reports failure");
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .filter_map(|e| e.ok().and_then(|e| e.file_name().into_string().ok()))
            .collect();
        assert!(names.iter().all(|n| !n.ends_with(".tmp")), "temporaries left: {names:?}");
        // Every file written is whole: the size of the first.
        let sizes: Vec<u64> = names
            .iter()
            .filter(|n| n.ends_with(".stl"))
            .map(|n| std::fs::metadata(dir.path().join(n)).unwrap().len())
            .collect();
        assert!(sizes.windows(2).all(|w| w[0] == w[1]), "{sizes:?}");
    }
}
